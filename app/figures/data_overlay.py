"""A data set drawn with a model: the data as its own trace on the model's figure (curves,
the 3-D lobe), the data's own image (the slice, the lit sphere), or the relative error
(data − model)/model one toggle away, titled with its largest value and where.

Curves get the data as markers on the model's own axes; a surface or an image is drawn by
the view's own figure function from the data's arrays, so it shares the view's scales
and conventions.
"""
from __future__ import annotations

import numpy as np

from .scale import colour_range, grid_weights, titled
from .style import axis, base_layout, gaps

#: the data trace's colour: black markers read against every palette colour of a model
DATA_COLOR = "#000000"
#: traces that become markers (curves) and the image types that are drawn on their own
CURVES = {"scatter", "scatterpolar"}
IMAGES = {"heatmap"}
#: how "where" names the overlay's axes
SYMBOLS = {"theta_o_deg": "θ_o", "theta_deg": "θ", "phi_deg": "φ_v", "mu": "μ", "theta_h_deg": "θ_h",
           "theta_d_deg": "θ_d"}
#: axis labels of the relative-error figure by the overlay's axis names
LABELS = {"theta_o_deg": "θ_o (degrees; > 0 on the mirror side)", "theta_deg": "θ (degrees)",
          "mu": "μ = cos θ_v", "theta_h_deg": "θ_h (degrees)", "theta_d_deg": "θ_d (degrees)",
          "phi_deg": "φ_v (degrees)", "x": "x (sphere radii)", "y": "y (sphere radii)"}

#: headroom above the data's largest value on a linear radius (the model's own lobe uses
#: the same 5 %), in decades on a log one, and either side of a curve's widened y range
RADIAL_PAD = 1.05
RADIAL_PAD_DECADES = 0.1
CURVE_PAD = 0.05

#: (rows, columns) of the images whose axes share a unit: drawn with a locked aspect
SQUARE = {("y", "x"), ("theta_d_deg", "theta_h_deg")}


def where_text(result: dict) -> str:
    """"largest +7.0 % at θ_o = 62°" (or that nothing could be compared)."""
    if result["max_relative_error"] is None:
        return "no point where both the data and a positive model value exist"
    at = ", ".join(f"{SYMBOLS.get(name, name)} = {value:.3g}{'°' if name.endswith('_deg') else ''}"
                   for name, value in result["where"].items())
    return f"largest {100 * result['max_relative_error']:+.2f} % at {at}"


def with_data(model_figure: dict, result: dict, label: str, data_figure: dict | None = None) -> dict:
    """The model's figure with the data added as markers (curves: on the model's own axes),
    a translucent grey surface (the 3-D lobe: ``data_figure``'s, drawn by the view from
    the data), or — for an image — ``data_figure`` itself, retitled."""
    kind = model_figure["data"][0].get("type", "scatter")
    if kind in IMAGES:
        layout = dict(data_figure["layout"], title=_retitled(data_figure, f"Data {label} — "
                                                                          f"{where_text(result)}"))
        return {"data": data_figure["data"], "layout": layout}
    name = f"data {label}"
    if kind == "scatterpolar":
        (theta,) = result["axes"].values()
        trace = {"type": "scatterpolar", "theta": theta, "r": gaps(result["data"])}
    elif kind in CURVES:
        (x,) = result["axes"].values()
        trace = {"type": "scatter", "x": x, "y": gaps(result["data"])}
        if result.get("data_error") is not None:
            trace["error_y"] = {"type": "data", "array": result["data_error"], "visible": True,
                                "thickness": 1, "color": DATA_COLOR}
    else:   # a surface: the data's, translucent and grey, through the model's
        trace = dict(data_figure["data"][0], opacity=0.45, colorscale="Greys", showscale=False)
    if kind in CURVES:
        trace.update(mode="markers", marker={"color": DATA_COLOR, "size": 5, "symbol": "circle-open"})
    trace.update(name=name, showlegend=True)
    out = {"data": [*model_figure["data"], trace], "layout": dict(model_figure["layout"])}
    if kind in CURVES:
        _cover(out, trace, result.get("data_error"))
    out["layout"]["title"] = _retitled(model_figure, f"{_text(model_figure)}<br>{name}: "
                                                     f"(data − model)/model {where_text(result)}")
    return out


def _cover(figure: dict, trace: dict, error) -> None:
    """Widen the model's value axis (the polar lobe's radius, a curve's y) to the data's
    finite values too (± their error bars): a peak of 3.75 on an axis sized to the model's
    1.47 was cut off, the very thing the overlay exists to show. A log radius keeps the
    model's bottom; the guide lines (directions) reach the new top."""
    values = np.asarray(trace.get("r", trace.get("y")), dtype=float)
    err = np.zeros_like(values) if error is None else np.asarray(error, dtype=float)
    finite = np.isfinite(values)
    if not finite.any():
        return
    low = float(np.min((values - np.where(np.isfinite(err), err, 0.0))[finite]))
    high = float(np.max((values + np.where(np.isfinite(err), err, 0.0))[finite]))
    layout = figure["layout"]
    if trace["type"] == "scatterpolar":
        polar = dict(layout.get("polar") or {})
        radial = dict(polar.get("radialaxis") or {})
        rng = radial.get("range")
        if not isinstance(rng, list) or high <= 0:
            return
        log = radial.get("type") == "log"
        top = np.log10(high) + RADIAL_PAD_DECADES if log else high * RADIAL_PAD
        if top <= rng[1]:
            return
        radial["range"] = [rng[0], float(top)]
        layout["polar"] = {**polar, "radialaxis": radial}
        reach = float(10 ** top) if log else float(top)
        figure["data"] = [dict(t, r=[t["r"][0], reach]) if _is_guide(t) else t for t in figure["data"]]
        return
    yaxis = layout.get("yaxis")
    if isinstance(yaxis, dict) and isinstance(yaxis.get("range"), list):
        lo, hi = yaxis["range"]
        pad = CURVE_PAD * max(high - low, hi - lo)
        new = [min(lo, low - pad) if low < lo else lo, max(hi, high + pad) if high > hi else hi]
        if new[0] < 0 <= lo:
            new[0] = 0.0 if low >= 0 else new[0]
        layout["yaxis"] = {**yaxis, "range": [float(new[0]), float(new[1])]}


def _is_guide(trace: dict) -> bool:
    meta = trace.get("meta")
    return isinstance(meta, dict) and meta.get("role") == "guide"


def _text(figure: dict) -> str:
    title = figure.get("layout", {}).get("title")
    return title.get("text", "") if isinstance(title, dict) else str(title or "")


def _retitled(figure: dict, text: str) -> dict:
    """The figure's title style with a new text."""
    title = figure.get("layout", {}).get("title")
    return {**(title if isinstance(title, dict) else {}), "text": text}


def relative_error(result: dict, label: str) -> dict:
    """(data − model)/model in per cent on the overlay's axes: a curve, or an image with
    a diverging scale centred on 0."""
    names = list(result["axes"])
    values = 100.0 * gaps(result["relative_error"])
    title = f"(data − model)/model, {label} — {where_text(result)}"
    if len(names) == 1:
        x = result["axes"][names[0]]
        trace = {"type": "scatter", "mode": "lines+markers", "x": x, "y": values,
                 "name": "(data − model)/model (%)", "marker": {"size": 4, "color": DATA_COLOR},
                 "line": {"color": DATA_COLOR, "width": 1}}
        return {"data": [trace], "layout": base_layout(
            title, xaxis=axis(LABELS.get(names[0], names[0])), yaxis=axis("relative error (%)"))}
    rows, columns = names
    # the scale's half-width from the area-weighted quantile of |error| (figures/scale.py):
    # one cell at a grazing divergence does not wash out the rest
    scale = colour_range(np.abs(values), grid_weights(result["axes"][rows], result["axes"][columns]))
    limit = scale.top if scale.top else 1.0
    trace = {"type": "heatmap", "x": result["axes"][columns], "y": result["axes"][rows], "z": values,
             "colorscale": "RdBu", "zmid": 0.0, "zmin": -limit, "zmax": limit, "hoverongaps": False,
             "colorbar": {"title": {"text": titled("%", scale)}, "thickness": 14}}
    # an image whose two axes share a unit keeps its aspect (the sphere is round)
    square = {"scaleanchor": "x", "constrain": "domain"} if (rows, columns) in SQUARE else {}
    return {"data": [trace], "layout": base_layout(
        title, xaxis=axis(LABELS.get(columns, columns), **({"constrain": "domain"} if square else {})),
        yaxis=axis(LABELS.get(rows, rows), **square))}
