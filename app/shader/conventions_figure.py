"""The ``conventions`` figure: the α each ecosystem means by one roughness, and its lobe."""
from __future__ import annotations

import numpy as np

from ..figures.style import PALETTE, axis, base_layout
from ..model import make_spec
from ..physics.vectors import direction_deg
from .conventions import ALPHA_MAX, ALPHA_MIN, table

#: angle of incidence of the lobes shown (degrees)
THETA_I_DEG = 45.0
LOBE_POINTS = 361


def lobe(row: dict) -> tuple[np.ndarray, np.ndarray]:
    """f(θ_o) of GGX at the ecosystem's α (clipped to the evaluated range) in the plane of
    incidence, θ_o > 0 on the mirror side; UE4's G rows with their Schlick-GGX k."""
    ax, ay = (float(np.clip(a, ALPHA_MIN, ALPHA_MAX)) for a in (row["alpha"], row["alpha_y"]))
    masking = "smith"
    if row["ecosystem"].startswith("UE4, G direct"):
        masking = "schlick_direct"
    elif row["ecosystem"].startswith("UE4, G image"):
        masking = "schlick_ibl"
    spec = make_spec(ndf="ggx", alpha=ax, alpha_y=None if ay == ax else ay, masking=masking, fresnel="none")
    theta_o = np.linspace(-89.5, 89.5, LOBE_POINTS)
    l = direction_deg(THETA_I_DEG, 0.0)
    v = direction_deg(np.abs(theta_o), np.where(theta_o >= 0, 180.0, 0.0))
    return theta_o, spec.brdf().evaluate(np.broadcast_to(l, v.shape), v, ("f",))["f"]


def conventions_figure(roughness: float, anisotropy: float) -> dict:
    rows = table(roughness, anisotropy)
    names = [r["ecosystem"] for r in rows]
    traces = [{"type": "bar", "x": names, "y": [r["alpha"] for r in rows], "name": "α (α_x)",
               "marker": {"color": PALETTE[0]}, "xaxis": "x", "yaxis": "y",
               "hovertemplate": "%{x}<br>α=%{y:.4g}<extra></extra>"}]
    if anisotropy > 0:
        traces.append({"type": "bar", "x": names, "y": [r["alpha_y"] for r in rows], "name": "α_y",
                       "marker": {"color": PALETTE[5]}, "xaxis": "x", "yaxis": "y",
                       "hovertemplate": "%{x}<br>α_y=%{y:.4g}<extra></extra>"})
    for k, row in enumerate(rows):
        theta, f = lobe(row)
        traces.append({"type": "scatter", "mode": "lines", "name": row["ecosystem"], "x": theta,
                       "y": np.where(f > 0, f, np.nan), "xaxis": "x2", "yaxis": "y2",
                       "line": {"color": PALETTE[k % len(PALETTE)], "width": 1.8,
                                "dash": ["solid", "dash", "dot", "dashdot"][k // len(PALETTE) % 4]},
                       "hovertemplate": f"{row['ecosystem']}<br>θ_o=%{{x:.1f}}°<br>f=%{{y:.4g}}<extra></extra>"})
    title = (f"One roughness r = {roughness:g}" + (f", anisotropy {anisotropy:g}" if anisotropy else "")
             + f": the α each ecosystem means, and its GGX lobe (θ_i = {THETA_I_DEG:g}°, F = 1)")
    layout = base_layout(title, barmode="group", showlegend=True, height=640,
                         xaxis=axis("", domain=[0.0, 1.0], anchor="y", tickangle=-20),
                         yaxis=axis("α (log)", type="log", domain=[0.62, 1.0]),
                         xaxis2=axis("θ_o (degrees; > 0 mirror side)", domain=[0.0, 1.0], anchor="y2"),
                         yaxis2=axis("f (log)", type="log", domain=[0.0, 0.46], anchor="x2"),
                         legend={"orientation": "v", "x": 1.01, "y": 0.46, "yanchor": "top"},
                         shapes=[{"type": "rect", "xref": "x domain", "yref": "y", "x0": 0, "x1": 1,
                                  "y0": ALPHA_MIN, "y1": ALPHA_MAX, "fillcolor": "#e8f1f8", "line": {"width": 0},
                                  "layer": "below"}],
                         margin={"l": 60, "r": 230, "t": 46, "b": 50})
    return {"data": traces, "layout": layout}
