"""Figures that are images: the lit sphere and the θ_h/θ_d slice (Disney explorer).

Presentation only: colour maps, log scaling for display, the sRGB transfer curve of a
screen. The values come from ``quantities``.
"""
from __future__ import annotations

import numpy as np

from .markup import subscripted
from .scale import ColourRange, colour_range, grid_weights, titled
from .sphere_image import srgb_encode
from .style import DIRECTION_COLORS, axis, base_layout, gaps, model_title

# Sequential and readable with colour-vision deficiency (Nuñez, Anderton, Renslow 2018,
# PLoS ONE 13(7): e0199239); the same map as the G2 heatmap.
SEQUENTIAL = "Cividis"
# Decades below the peak a log image shows; darker than that is drawn as the floor.
IMAGE_DECADES = 6
#: Most labels on an image's log colour bar (the bar is short on a square image in half a
#: page: about 50 px under its title at 1280 × 800).
COLOUR_BAR_LABELS = 3

# Background of a rendered sphere (a dark studio), and of a slice's impossible region.
RENDER_BACKGROUND = "#202020"
NO_PAIR_GREY = "#d0d0d0"
# Display value 0 → black, 1 → white (explicit: plotly.py's and plotly.js's "Greys" run
# in opposite directions).
GREY_RAMP = [[0.0, "#000000"], [1.0, "#ffffff"]]


def _log_z(values: np.ndarray, scale: ColourRange):
    """log10 of the values for a log colour scale from IMAGE_DECADES below the scale's top
    (scale.py: a high quantile of the finite values, not their maximum) to the top; darker
    values are drawn as the floor; gaps (NaN) stay gaps. Returns z, zmin, zmax and the
    colour bar's ticks (at most COLOUR_BAR_LABELS, whole decades apart)."""
    v = gaps(values)
    if scale.top is None or scale.top <= 0.0:
        return np.where(np.isfinite(v), 0.0, np.nan), 0.0, 1.0, {}
    top = float(np.log10(scale.top))
    floor = 10.0 ** (top - IMAGE_DECADES)
    with np.errstate(invalid="ignore"):        # NaN (a gap) compares false: stays NaN
        z = np.log10(np.where(v > floor, v, np.where(np.isnan(v), np.nan, floor)))
    # at most COLOUR_BAR_LABELS labels, a whole number of decades apart and the top one
    # included: six decade labels overlapped on the bar of an image in half a page
    decades = np.arange(np.ceil(top - IMAGE_DECADES), np.floor(top) + 1)
    step = int(np.ceil(decades.size / COLOUR_BAR_LABELS))
    ticks = decades[::-1][::step][::-1]
    return z, top - IMAGE_DECADES, top, {"tickvals": ticks,
                                         "ticktext": [f"10<sup>{int(k)}</sup>" for k in ticks]}


@subscripted
def lit_sphere_figure(data: dict, spec: dict, theta_i_deg: float, phi_i_deg: float,
                      display: str = "heatmap", exposure: float = 0.0) -> dict:
    x, y = np.asarray(data["x"]), np.asarray(data["y"])
    L = gaps(data["radiance"])
    label = "L<sub>o</sub>/E (1/sr)"
    trace = {"type": "heatmap", "x": x, "y": y, "hoverongaps": False,
             "hovertemplate": "x=%{x:.3f}<br>y=%{y:.3f}<br>L/E=%{customdata:.4g}<extra></extra>",
             "customdata": L}
    if display == "render":
        trace.update(z=srgb_encode(L * 2.0 ** exposure), zmin=0.0, zmax=1.0, colorscale=GREY_RAMP,
                     showscale=False)
        what = f"rendered, sRGB, exposure {exposure:+g}"
    elif display == "log":
        scale = colour_range(L)
        z, lo, hi, ticks = _log_z(L, scale)
        trace.update(z=z, zmin=lo, zmax=hi, colorscale=SEQUENTIAL,
                     colorbar={"title": {"text": titled(label, scale)}, "thickness": 14, **ticks})
        what = "log scale"
    else:
        scale = colour_range(L)
        trace.update(z=L, zmin=0.0, zmax=scale.top if scale.top and scale.top > 0 else 1.0,
                     colorscale=SEQUENTIAL,
                     colorbar={"title": {"text": titled(label, scale)}, "thickness": 14})
        what = "L_o/E = f·cos θ_l"
    ti, pi = np.deg2rad(theta_i_deg), np.deg2rad(phi_i_deg)
    light = np.array([np.sin(ti) * np.cos(pi), np.sin(ti) * np.sin(pi), np.cos(ti)])
    h = light + np.array([0.0, 0.0, 1.0])
    h /= np.linalg.norm(h)
    circle = np.linspace(0.0, 2.0 * np.pi, 181)
    guides = [
        {"type": "scatter", "mode": "lines", "x": np.cos(circle), "y": np.sin(circle),
         "name": "silhouette", "line": {"color": "#888888", "width": 1}, "hoverinfo": "skip",
         "showlegend": False, "meta": {"role": "guide"}},
        {"type": "scatter", "mode": "markers", "x": [light[0]], "y": [light[1]],
         "name": "n = l (faces the light)", "meta": {"role": "guide"},
         "marker": {"symbol": "circle-open", "size": 11, "line": {"width": 2.5},
                    "color": DIRECTION_COLORS["incident"]}, "hoverinfo": "name"},
        {"type": "scatter", "mode": "markers", "x": [h[0]], "y": [h[1]],
         "name": "n = h (mirror point)", "meta": {"role": "guide"},
         "marker": {"symbol": "x-thin-open", "size": 11, "line": {"width": 2.5},
                    "color": DIRECTION_COLORS["mirror"]}, "hoverinfo": "name"},
    ]
    layout = base_layout(
        f"Lit sphere, {what} — {model_title(spec)}, light θ_i={theta_i_deg:g}°, φ_i={phi_i_deg:g}°",
        xaxis=axis("x (sphere radii)", range=[-1.05, 1.05], showgrid=False, constrain="domain",
                   dtick=0.5),
        yaxis=axis("y (sphere radii)", range=[-1.05, 1.05], showgrid=False, scaleanchor="x",
                   constrain="domain", dtick=0.5),
        legend={"orientation": "h", "y": -0.15, "x": 0})
    if display == "render":
        layout["plot_bgcolor"] = RENDER_BACKGROUND
    return {"data": [trace, *guides], "layout": layout}


@subscripted
def slice_figure(data: dict, spec: dict, phi_d_deg: float, log: bool = True) -> dict:
    key = "f_cos" if "f_cos" in data else "f"
    name = "f·cos θ_l" if key == "f_cos" else "f"
    values = gaps(data[key])
    theta_h, theta_d = np.asarray(data["theta_h_deg"]), np.asarray(data["theta_d_deg"])
    # the columns are refined toward features: each value weighs the area it covers
    scale = colour_range(values, grid_weights(theta_d, theta_h))
    colorbar = {"title": {"text": titled(f"{name} (1/sr)", scale)}, "thickness": 14}
    if log:
        z, lo, hi, ticks = _log_z(values, scale)
        colorbar.update(ticks)
    else:
        z, lo, hi = values, 0.0, scale.top if scale.top and scale.top > 0 else 1.0
    return {
        "data": [{"type": "heatmap", "x": theta_h, "y": theta_d, "z": z, "customdata": values,
                  "zmin": lo, "zmax": hi,
                  "colorscale": SEQUENTIAL, "colorbar": colorbar, "hoverongaps": False,
                  "hovertemplate": "θ_h=%{x:.1f}°<br>θ_d=%{y:.1f}°<br>" + name
                                   + "=%{customdata:.4g}<extra></extra>"}],
        "layout": base_layout(
            f"{name} over θ_h, θ_d at φ_d={phi_d_deg:g}° — {model_title(spec)}",
            xaxis=axis("θ_h (degrees): normal to half vector", range=[0, 90], dtick=15,
                       constrain="domain"),
            # short enough for a square image in half a page (a longer title ran past
            # the image's top into the label above it)
            yaxis=axis("θ_d (degrees): h to l", range=[0, 90], dtick=15,
                       scaleanchor="x", constrain="domain"),
            plot_bgcolor=NO_PAIR_GREY,
            annotations=[{"text": "grey: l or v below the horizon", "xref": "paper",
                          "yref": "paper", "x": 1.0, "y": 1.0, "xanchor": "right",
                          "yanchor": "bottom", "showarrow": False, "font": {"size": 11}}]),
    }
