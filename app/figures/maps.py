"""Figures of a quantity over two angles: G2(θ_l, θ_v) as a heatmap."""
from __future__ import annotations

import numpy as np

from .markup import subscripted
from .style import axis, base_layout, gaps, model_title
from .titles import option_label as _option_label


# Cividis: sequential, perceptually uniform and readable with colour-vision deficiency
# (Nuñez, Anderton, Renslow 2018, PLoS ONE 13(7): e0199239).
SEQUENTIAL = "Cividis"


def _g2_label(name: str) -> str:
    return _option_label("g2", name)


def g2_title(spec: dict, phi_deg: float) -> str:
    # the G2 form is named even where it is the default: it is what the map shows
    form = _g2_label(spec["g2"]).lower()
    return f"G2(θ_l, θ_v), {form} — {model_title(spec)}, φ={phi_deg:g}°"


@subscripted
def g2_figure(data: dict, spec: dict, phi_deg: float) -> dict:
    theta_l = np.asarray(data["theta_l_deg"])
    theta_v = np.asarray(data["theta_v_deg"])
    return {
        "data": [{"type": "heatmap", "x": theta_v, "y": theta_l, "z": gaps(data["G2"]),
                  "zmin": 0.0, "zmax": 1.0, "colorscale": SEQUENTIAL,
                  "colorbar": {"title": {"text": "G2"}, "thickness": 14},
                  "hovertemplate": "θ_l=%{y:.1f}°<br>θ_v=%{x:.1f}°<br>G2=%{z:.5f}<extra></extra>"}],
        "layout": base_layout(
            g2_title(spec, phi_deg),
            xaxis=axis("θ_v (degrees)", range=[0, 90], dtick=15, constrain="domain"),
            yaxis=axis("θ_l (degrees)", range=[0, 90], dtick=15, scaleanchor="x",
                       constrain="domain"),
            margin={"l": 60, "r": 20, "t": 46, "b": 50}),
    }
