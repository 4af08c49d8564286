"""The ``conventions`` figure: the α each ecosystem means by one roughness (bars), and
the GGX lobe at each (curves). No physics: the rows come from app/shader/conventions.py
and each row's lobe from quantities.conventions_lobes."""
from __future__ import annotations

import numpy as np

from .style import PALETTE, axis, base_layout


def conventions_figure(data: dict, roughness: float, anisotropy: float) -> dict:
    """``data``: quantities.conventions_lobes — the rows, each with its lobe f(θ_o), the
    angle of incidence and the evaluated α range (shaded)."""
    rows, theta_i = data["rows"], data["theta_i_deg"]
    alpha_min, alpha_max = data["alpha_range"]
    names = [r["ecosystem"] for r in rows]
    traces = [{"type": "bar", "x": names, "y": [r["alpha"] for r in rows], "name": "α (α_x)",
               "marker": {"color": PALETTE[0]}, "xaxis": "x", "yaxis": "y",
               "hovertemplate": "%{x}<br>α=%{y:.4g}<extra></extra>"}]
    if anisotropy > 0:
        traces.append({"type": "bar", "x": names, "y": [r["alpha_y"] for r in rows], "name": "α_y",
                       "marker": {"color": PALETTE[5]}, "xaxis": "x", "yaxis": "y",
                       "hovertemplate": "%{x}<br>α_y=%{y:.4g}<extra></extra>"})
    for k, row in enumerate(rows):
        theta, f = row["theta_o_deg"], row["f"]
        traces.append({"type": "scatter", "mode": "lines", "name": row["ecosystem"], "x": theta,
                       "y": np.where(f > 0, f, np.nan), "xaxis": "x2", "yaxis": "y2",
                       "line": {"color": PALETTE[k % len(PALETTE)], "width": 1.8,
                                "dash": ["solid", "dash", "dot", "dashdot"][k // len(PALETTE) % 4]},
                       "hovertemplate": f"{row['ecosystem']}<br>θ_o=%{{x:.1f}}°<br>f=%{{y:.4g}}<extra></extra>"})
    title = (f"One roughness r = {roughness:g}" + (f", anisotropy {anisotropy:g}" if anisotropy else "")
             + f": the α each ecosystem means, and its GGX lobe (θ_i = {theta_i:g}°, F = 1)")
    layout = base_layout(title, barmode="group", showlegend=True, height=640,
                         xaxis=axis("", domain=[0.0, 1.0], anchor="y", tickangle=-20),
                         yaxis=axis("α (log)", type="log", domain=[0.62, 1.0]),
                         xaxis2=axis("θ_o (degrees; > 0 mirror side)", domain=[0.0, 1.0], anchor="y2"),
                         yaxis2=axis("f (log)", type="log", domain=[0.0, 0.46], anchor="x2"),
                         legend={"orientation": "v", "x": 1.01, "y": 0.46, "yanchor": "top"},
                         shapes=[{"type": "rect", "xref": "x domain", "yref": "y", "x0": 0, "x1": 1,
                                  "y0": alpha_min, "y1": alpha_max, "fillcolor": "#e8f1f8", "line": {"width": 0},
                                  "layer": "below"}],
                         margin={"l": 60, "r": 230, "t": 46, "b": 50})
    return {"data": traces, "layout": layout}
