"""Figures of the lobe: f in the plane of incidence (polar) and over the hemisphere (3D)."""
from __future__ import annotations

import numpy as np

from .markup import subscripted
from .scale import cell_widths, colour_range, titled
from .style import DIRECTION_COLORS, PALETTE, base_layout, gaps, model_title

# Decades below the peak shown by the log-scale polar lobe.
LOBE_DECADES = 5


def _polar_radius_range(r: np.ndarray, log: bool):
    finite = r[np.isfinite(r) & (r > 0)]
    if finite.size == 0:
        return None
    if log:
        hi = np.log10(finite.max())
        return [hi - LOBE_DECADES, hi + 0.1]
    return [0, float(finite.max()) * 1.05]


@subscripted
def lobe_figure(data: dict, spec: dict, theta_i_deg: float, log: bool = False) -> dict:
    key = "f_cos" if "f_cos" in data else "f"
    theta_o = np.asarray(data["theta_o_deg"])
    r = gaps(data[key])
    if log:
        r = np.where(r > 0, r, np.nan)
    rng = _polar_radius_range(r, log)
    top = (10 ** rng[1]) if (log and rng) else (rng[1] if rng else 1.0)
    directions = [("normal n", 0.0, DIRECTION_COLORS["normal"]),
                  ("incident l", -theta_i_deg, DIRECTION_COLORS["incident"]),
                  ("mirror", theta_i_deg, DIRECTION_COLORS["mirror"])]
    bottom = 10 ** rng[0] if (log and rng) else 0.0
    traces = [{"type": "scatterpolar", "mode": "lines",
               "name": "f·cos θ_o (1/sr)" if key == "f_cos" else "f (1/sr)",
               "theta": theta_o, "r": r, "line": {"color": PALETTE[0], "width": 2.5},
               "fill": "toself" if not log else None, "fillcolor": "rgba(0,114,178,0.12)",
               "hovertemplate": "θ_o=%{theta:.1f}°<br>%{r:.4g}<extra></extra>"}]
    for name, angle, color in directions:
        traces.append({"type": "scatterpolar", "mode": "lines", "name": name,
                       "theta": [angle, angle], "r": [bottom, top],
                       "line": {"color": color, "width": 1.5, "dash": "dash"},
                       "hoverinfo": "skip", "meta": {"role": "guide"}})
    # No radial title: it collides with the tick labels along the normal; the legend and
    # the figure title say what r is.
    radial = {"type": "log" if log else "linear", "angle": 90, "tickangle": 90,
              "exponentformat": "power", "gridcolor": "#e5e5e5"}
    if log:
        radial["dtick"] = 1
    if rng:
        radial["range"] = rng
    label = "f·cos θ_o" if key == "f_cos" else "f(l, v)"
    return {
        "data": traces,
        "layout": base_layout(
            f"{label} in the plane of incidence — {model_title(spec)}, θ_i={theta_i_deg:g}°",
            polar={"sector": [0, 180], "bgcolor": "white",
                   "angularaxis": {"rotation": 90, "direction": "clockwise", "dtick": 15,
                                   "gridcolor": "#e5e5e5", "ticksuffix": "°"},
                   "radialaxis": radial},
            margin={"l": 30, "r": 30, "t": 50, "b": 10},
            legend={"orientation": "h", "y": 0.02, "x": 0.5, "xanchor": "center"}),
    }


@subscripted
def lobe3d_figure(data: dict, spec: dict, theta_i_deg: float, phi_i_deg: float,
                  log: bool = False) -> dict:
    theta = np.deg2rad(np.asarray(data["theta_deg"]))[:, None]
    phi = np.deg2rad(np.asarray(data["phi_deg"]))[None, :]
    f = gaps(data["f"])
    # the colour stops at the scale's top (scale.py): a spike or a grazing divergence
    # covering < 0.1 % of the hemisphere's solid angle does not set it (the radius still
    # draws the lobe's true shape; a divergence is a gap)
    solid_angle = np.sin(theta) * cell_widths(theta[:, 0])[:, None] * cell_widths(phi[0])[None, :]
    scale = colour_range(f, solid_angle)
    top = scale.top if scale.top and scale.top > 0 else 1.0
    if log:
        positive = f[np.isfinite(f) & (f > 0)]
        floor = positive.max() * 1e-6 if positive.size else 1.0
        # gaps (NaN) stay gaps: np.maximum and log10 propagate NaN silently.
        radius = np.log10(np.maximum(f, floor) / floor)
        colour_top = float(np.log10(max(top, floor) / floor))
        label = "log<sub>10</sub>(f/f<sub>floor</sub>)"
    else:
        radius, colour_top, label = f, top, "f (1/sr)"
    x = radius * np.sin(theta) * np.cos(phi)
    y = radius * np.sin(theta) * np.sin(phi)
    z = radius * np.cos(theta)
    rmax = float(np.nanmax(radius)) if np.isfinite(radius).any() else 1.0
    ti, pi = np.deg2rad(theta_i_deg), np.deg2rad(phi_i_deg)
    l = np.array([np.sin(ti) * np.cos(pi), np.sin(ti) * np.sin(pi), np.cos(ti)])
    mirror = np.array([-l[0], -l[1], l[2]])
    traces = [{"type": "surface", "x": x, "y": y, "z": z, "surfacecolor": radius,
               "colorscale": "Viridis", "showscale": True, "name": "f", "cmin": 0.0, "cmax": colour_top,
               "colorbar": {"title": {"text": titled(label, scale)}, "thickness": 14},
               "hovertemplate": "f-radius=%{surfacecolor:.4g}<extra></extra>"}]
    for name, d, color in [("normal n", np.array([0, 0, 1.0]), DIRECTION_COLORS["normal"]),
                           ("incident l", l, DIRECTION_COLORS["incident"]),
                           ("mirror", mirror, DIRECTION_COLORS["mirror"])]:
        traces.append({"type": "scatter3d", "mode": "lines", "name": name,
                       "x": [0, d[0] * rmax * 1.1], "y": [0, d[1] * rmax * 1.1],
                       "z": [0, d[2] * rmax * 1.1], "line": {"color": color, "width": 5},
                       "meta": {"role": "guide"}})
    return {
        "data": traces,
        "layout": base_layout(
            f"3D lobe {'(log radius, 6 decades)' if log else 'f(l, v)'} — {model_title(spec)}, "
            f"θ_i={theta_i_deg:g}°, φ_i={phi_i_deg:g}°",
            scene={"aspectmode": "data", "xaxis": {"title": {"text": "x (t)"}},
                   "yaxis": {"title": {"text": "y (b)"}}, "zaxis": {"title": {"text": "z (n)"}},
                   "camera": {"eye": {"x": 1.4, "y": -1.4, "z": 0.9}}},
            margin={"l": 0, "r": 0, "t": 46, "b": 0}),
    }
