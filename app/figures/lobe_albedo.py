"""The stacked albedo chart: how much each lobe of a model reflects, E(θ_v) per lobe
stacked to the total (the ``principled_albedo`` view; Plotly figure dict, no physics).
The lobes are drawn in the order the data lists them."""
from __future__ import annotations

import numpy as np

from .style import PALETTE

#: the principled lobes' colours; any other lobe takes the palette's
COLOURS = {"diffuse": "#c77c2e", "sheen": "#8f6bb3", "specular": "#3a78b5", "clearcoat": "#3aa37a"}


def stacked_albedo_figure(data: dict, title: str) -> dict:
    theta = np.degrees(np.arccos(np.clip(data["mu"], 0.0, 1.0)))
    order = np.argsort(theta)
    traces = []
    for i, lobe in enumerate(data["lobes"]):
        E = np.asarray(data["lobes"][lobe]["E"])[order]
        traces.append({"type": "scatter", "mode": "lines", "name": f"{lobe} (E_avg "
                       f"{data['lobes'][lobe]['E_avg']:.3f})", "x": theta[order].tolist(),
                       "y": E.tolist(), "stackgroup": "albedo",
                       "line": {"color": COLOURS.get(lobe, PALETTE[i % len(PALETTE)])},
                       "hovertemplate": f"{lobe}: %{{y:.4f}}<extra></extra>"})
    traces.append({"type": "scatter", "mode": "lines", "name": "white furnace (E = 1)", "x": [0, 90],
                   "y": [1, 1], "line": {"dash": "dot", "color": "#777"}})
    return {"data": traces,
            "layout": {"title": {"text": title}, "xaxis": {"title": {"text": "θ_v (deg)"}, "range": [0, 90]},
                       "yaxis": {"title": {"text": f"E(θ_v), {data['channel']}, stacked"},
                                 "rangemode": "tozero"},
                       "legend": {"orientation": "h"}}}
