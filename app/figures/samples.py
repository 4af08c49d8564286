"""Sampled directions against their pdf on the hemisphere, in (cos θ_l, φ_l).

Left: the density of the samples (Plotly bins them, each sample weighing
1 / (N · bin solid angle): Δcos θ times the bin's φ width in radians, so the density
is per steradian; φ is drawn in degrees, as every angle the page shows). Right: the pdf at the same samples, averaged per bin (what the left panel
should show, up to noise and the variation of the pdf within a bin). The χ² statistic
and p-value in the title come from ``quantities.samples`` (exact bin integrals).
"""
from __future__ import annotations

import numpy as np

from .maps import SEQUENTIAL
from .markup import subscripted
from .style import axis, base_layout, model_title

#: bins per axis of the two heatmaps (cos θ, φ): Plotly's histogram2d bins client-side
FIGURE_BINS = (24, 48)


@subscripted
def samples_figure(data: dict, spec: dict, theta_i_deg: float) -> dict:
    z = np.asarray(data["z"], dtype=float)
    upper = z >= 0
    phi = np.degrees(np.arctan2(np.asarray(data["y"], dtype=float),
                                np.asarray(data["x"], dtype=float)))[upper]
    cos_t = z[upper]
    pdf = np.asarray(data["pdf"], dtype=float)[upper]
    n_cos, n_phi = FIGURE_BINS
    bins = {"xbins": {"start": -180.0, "end": 180.0, "size": 360.0 / n_phi},
            "ybins": {"start": 0.0, "end": 1.0, "size": 1.0 / n_cos}, "autobinx": False, "autobiny": False}
    n = len(z)
    cmax = float(np.max(pdf)) if pdf.size else 1.0
    common = {"x": phi, "y": cos_t, "colorscale": SEQUENTIAL, "zmin": 0.0, "zmax": cmax, **bins}
    title = (f"Samples ({data['sampler']}, N={n}, seed={data['seed']}) vs pdf — {model_title(spec)}, "
             f"θ={theta_i_deg:g}°<br>χ²={data['chi2']:.1f}, dof={data['dof']}, p={data['p_value']:.3g}; "
             f"below horizon {data['below_horizon']} (expected {data['below_horizon_expected']:.1f}); "
             f"E={data['E']:.5f} ± {data['E_error']:.1g}")
    return {
        "data": [
            # each sample adds 1/(N · bin solid angle): the bin sums are the density of all
            # N samples per steradian (the pdf is normalised over the whole sphere); φ is
            # drawn in degrees, the solid angle takes the bin's width in radians
            {"type": "histogram2d", "histfunc": "sum", "name": "sampled density", **common,
             "z": np.full(cos_t.size, 1.0 / (n * (2 * np.pi / n_phi) * (1.0 / n_cos))),
             "colorbar": {"title": {"text": "1/sr"}, "thickness": 14},
             "hovertemplate": "φ=%{x:.1f}°<br>cos θ=%{y:.3f}<br>density=%{z:.4g}<extra></extra>",
             "xaxis": "x", "yaxis": "y"},
            {"type": "histogram2d", "histfunc": "avg", "name": "pdf (mean per bin)", **common,
             "z": pdf, "showscale": False, "xaxis": "x2", "yaxis": "y2",
             "hovertemplate": "φ=%{x:.1f}°<br>cos θ=%{y:.3f}<br>pdf=%{z:.4g}<extra></extra>"},
        ],
        "layout": base_layout(
            title,
            xaxis=axis("φ_l (degrees) — sampled", domain=[0.0, 0.44], range=[-180, 180], dtick=90),
            yaxis=axis("cos θ_l", range=[0, 1]),
            xaxis2=axis("φ_l (degrees) — pdf", domain=[0.52, 0.96], range=[-180, 180], dtick=90),
            yaxis2=axis("", range=[0, 1], anchor="x2"),
            margin={"l": 60, "r": 20, "t": 70, "b": 50}),
    }
