"""Figure of the Fresnel reflectance F(θ_d) and, for an approximation, its error."""
from __future__ import annotations

import numpy as np

from .markup import subscripted
from .style import PALETTE, axis, base_layout
from .titles import fresnel_text

def fresnel_title(spec: dict) -> str:
    """"Fresnel F(θ_d) — Schlick F₀=0.04 F₉₀=1 p=5": the form and all its parameters
    (what the figure shows), the NDF left out (F does not depend on it)."""
    return f"Fresnel F(θ_d) — {fresnel_text(spec)}"


@subscripted
def fresnel_figure(data: dict, spec: dict) -> dict:
    theta = np.asarray(data["theta_deg"])
    traces = [{"type": "scatter", "mode": "lines", "name": f"F (F̄ = {data['F_avg']:.4f})",
               "x": theta, "y": data["F"], "line": {"color": PALETTE[0], "width": 2.5},
               "hovertemplate": "θ_d=%{x:.2f}°<br>F=%{y:.5f}<extra></extra>"}]
    extra = {}
    if "F_exact" in data:
        exact = data["F_exact_model"]
        label = ", ".join(f"{k}={v:.4g}" for k, v in exact.items()
                          if k != "fresnel" and v is not None and np.isfinite(v))
        traces += [
            {"type": "scatter", "mode": "lines", "name": f"exact {exact['fresnel']} ({label})",
             "x": theta, "y": data["F_exact"], "line": {"color": PALETTE[2], "width": 2, "dash": "dash"},
             "hovertemplate": "θ_d=%{x:.2f}°<br>F_exact=%{y:.5f}<extra></extra>"},
            {"type": "scatter", "mode": "lines", "name": "F − F_exact (right axis)",
             "x": theta, "y": data["F_error"], "yaxis": "y2",
             "line": {"color": PALETTE[1], "width": 1.5, "dash": "dot"},
             "hovertemplate": "θ_d=%{x:.2f}°<br>error=%{y:.3g}<extra></extra>"},
        ]
        # Symmetric about 0, so that the zero line sits mid-height and the sign of the
        # error reads at a glance; its own ticks (not synced to the F axis' grid).
        err = np.asarray(data["F_error"], dtype=float)
        top = float(np.max(np.abs(err[np.isfinite(err)]), initial=0.0)) * 1.1 or 1e-3
        extra = {"yaxis2": axis("F − F_exact", overlaying="y", side="right", showgrid=False,
                                range=[-top, top], tickmode="auto", nticks=7,
                                zeroline=True, zerolinecolor="#bbb", exponentformat="power"),
                 "margin": {"l": 60, "r": 70, "t": 46, "b": 50}}
    return {
        "data": traces,
        "layout": base_layout(
            fresnel_title(spec),
            xaxis=axis("θ_d, angle between v and h (degrees)", range=[0, 90], dtick=15),
            yaxis=axis("F", range=[0, 1.02]),
            **extra),
    }
