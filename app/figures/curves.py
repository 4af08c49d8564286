"""Figures of curves over an angle: D(θ), Λ and G1(θ), E(μ)."""
from __future__ import annotations

import numpy as np

from .markup import subscripted
from .style import PALETTE, axis, base_layout, gaps, log_axis, model_title
from .titles import option_label

# How many decades below the peak a log axis shows.
D_DECADES = 10
LAMBDA_DECADES = 8


@subscripted
def ndf_figure(data: dict, spec: dict, log: bool = True) -> dict:
    theta = np.asarray(data["theta_deg"])
    key, label = ("D_cos", "D(θ_m)·cos θ_m") if "D_cos" in data else ("D", "D(θ_m)")
    return {
        "data": [{"type": "scatter", "mode": "lines", "name": label, "x": theta,
                  "y": gaps(data[key]), "line": {"color": PALETTE[0], "width": 2},
                  "hovertemplate": "θ_m=%{x:.2f}°<br>" + label + "=%{y:.4g}<extra></extra>"}],
        "layout": base_layout(
            f"{label} — {model_title(spec)}",
            xaxis=axis("θ_m (degrees)", range=[0, 90], dtick=15),
            yaxis=(log_axis(f"{label} (1/sr)", data[key], D_DECADES) if log
                   else axis(f"{label} (1/sr)")),
            showlegend=False),
    }


@subscripted
def g1_figure(data: dict, spec: dict) -> dict:
    """G1 with Λ on a log right axis; for an approximate masking, G1 with the exact Smith
    G1 dotted and the error G1 − G1_exact on the right axis instead."""
    theta = np.asarray(data["theta_deg"])
    traces = [{"type": "scatter", "mode": "lines", "name": "G1(θ_v)", "x": theta,
               "y": gaps(data["G1"]), "line": {"color": PALETTE[0], "width": 2},
               "hovertemplate": "θ=%{x:.2f}°<br>G1=%{y:.5f}<extra></extra>"}]
    if "G1_error" in data:
        error = np.asarray(data["G1_error"], dtype=float)
        span = max(float(np.max(np.abs(error))), 1e-12) * 1.1
        traces += [
            {"type": "scatter", "mode": "lines", "name": "G1 exact (Smith)", "x": theta,
             "y": gaps(data["G1_exact"]), "line": {"color": PALETTE[6], "width": 1.5, "dash": "dot"},
             "hovertemplate": "θ=%{x:.2f}°<br>exact G1=%{y:.5f}<extra></extra>"},
            {"type": "scatter", "mode": "lines", "name": "G1 − G1 exact (right axis)",
             "x": theta, "y": gaps(error), "yaxis": "y2",
             "line": {"color": PALETTE[1], "width": 2, "dash": "dash"},
             "hovertemplate": "θ=%{x:.2f}°<br>error=%{y:.3g}<extra></extra>"}]
        # its own round ticks: an overlaying axis's ticks default to the left axis's grid
        # (Plotly 3+), which labelled it 0.00309, 0.00179, −0.00081…
        right = axis("G1 − G1 exact", overlaying="y", side="right", showgrid=False,
                     range=[-span, span], tickmode="auto", nticks=7, zeroline=True,
                     zerolinecolor="#bbb", exponentformat="power")
        title = f"G1 ({option_label('masking', spec['masking'])}) against exact Smith — {model_title(spec)}"
    else:
        traces.append({"type": "scatter", "mode": "lines", "name": "Λ(θ_v) (right axis, log)",
                       "x": theta, "y": gaps(data["Lambda"]), "yaxis": "y2",
                       "line": {"color": PALETTE[1], "width": 2, "dash": "dash"},
                       "hovertemplate": "θ=%{x:.2f}°<br>Λ=%{y:.4g}<extra></extra>"})
        right = log_axis("Λ", data["Lambda"], LAMBDA_DECADES, overlaying="y", side="right",
                         showgrid=False)
        title = f"Smith G1 and Λ — {model_title(spec)}"
    return {
        "data": traces,
        "layout": base_layout(
            title,
            xaxis=axis("θ_v (degrees)", range=[0, 90], dtick=15),
            yaxis=axis("G1", range=[0, 1.05]),
            yaxis2=right,
            margin={"l": 60, "r": 60, "t": 46, "b": 50}),
    }


def _method_text(data: dict) -> str:
    """How E was computed and what its bar means, for the legend."""
    method = data.get("method", "quadrature")
    if method.startswith("mc_"):
        return f"{method}, {data['samples']} samples/μ, bar ±1 standard error"
    if method == "table":
        return f"table {data['table']['size']}, bar = its measured error bound"
    return "quadrature, bar = error bound"


#: Margin of a fitted albedo axis beyond the data, as a fraction of the data's span, and the
#: smallest span shown (E constant to 1e-6 still gets an axis one can read).
ALBEDO_PAD = 0.08
ALBEDO_MIN_SPAN = 0.02


def albedo_y_range(lows, highs, y_range: str = "fit") -> list[float]:
    """"unit": 0 to 1 (1.05, or above the largest E + error); "fit": the data's own span
    (E ± error, E_single, E_avg) with ALBEDO_PAD either side, so F₀ = 0.04 is not
    squashed into the bottom fifth of a 0-1 axis."""
    lo, hi = float(np.min(lows)), float(np.max(highs))
    if y_range == "unit":
        return [0.0, max(1.05, hi + 0.03)]
    span = max(hi - lo, ALBEDO_MIN_SPAN)
    mid = 0.5 * (lo + hi)
    return [max(0.0, mid - span * (0.5 + ALBEDO_PAD)), mid + span * (0.5 + ALBEDO_PAD)]


@subscripted
def albedo_figure(data: dict, spec: dict, y_range: str = "fit") -> dict:
    """E(μ) with its error band; ``y_range`` "fit" (the data's span) or "unit" (0-1)."""
    mu = np.asarray(data["mu"])
    E, err = np.asarray(data["E"]), np.asarray(data["E_error"])
    chosen = " (auto)" if data.get("requested_method") == "auto" else ""
    compensated = "E_single" in data
    traces = [
        {"type": "scatter", "mode": "lines", "x": np.concatenate([mu, mu[::-1]]),
         "y": np.concatenate([E + err, (E - err)[::-1]]), "fill": "toself",
         "fillcolor": "rgba(0,114,178,0.2)", "line": {"width": 0}, "hoverinfo": "skip",
         "name": "± error estimate", "showlegend": False},
        {"type": "scatter", "mode": "lines+markers",
         "name": f"E(μ){' with compensation' if compensated else ''}: {_method_text(data)}{chosen}",
         "x": mu, "y": E,
         "error_y": {"type": "data", "array": err, "visible": True, "thickness": 1},
         "line": {"color": PALETTE[0], "width": 2}, "marker": {"size": 5},
         "hovertemplate": "μ=%{x:.3f}<br>E=%{y:.6f}<extra></extra>"},
    ]
    if compensated:
        traces.append({
            "type": "scatter", "mode": "lines+markers", "x": mu, "y": np.asarray(data["E_single"]),
            "name": f"E_single(μ): single scattering (Ē = {data['E_avg_single']:.4f} at F = 1, "
                    f"F_avg = {data['F_avg']:.4f})",
            "line": {"color": PALETTE[1], "width": 1.5, "dash": "dash"}, "marker": {"size": 4},
            "hovertemplate": "μ=%{x:.3f}<br>E_single=%{y:.6f}<extra></extra>"})
    traces.append({"type": "scatter", "mode": "lines", "name": f"E_avg = {data['E_avg']:.5f}",
                   "x": [0, 1], "y": [data["E_avg"]] * 2,
                   "line": {"color": PALETTE[2], "width": 1.5, "dash": "dot"}, "hoverinfo": "skip"})
    annotations = []
    energy = data.get("energy") or {}
    if energy.get("creates_energy"):
        annotations.append({
            "text": f"E > 1 by {energy['excess']:.2g}, beyond its error {energy['error']:.1g}: "
                    "this model is not energy-conserving (k_d + specular exceeds 1)",
            "xref": "paper", "yref": "paper", "x": 0.5, "y": 1.0, "showarrow": False,
            "font": {"color": "#B00020", "size": 12}, "bgcolor": "rgba(255,255,255,0.85)"})
    shown = [E - err, [data["E_avg"]]] + ([data["E_single"]] if compensated else [])
    tops = [E + err, [data["E_avg"]]] + ([data["E_single"]] if compensated else [])
    y_axis_range = albedo_y_range(np.concatenate([np.ravel(x) for x in shown]),
                                  np.concatenate([np.ravel(x) for x in tops]), y_range)
    return {
        "data": traces,
        "layout": base_layout(
            f"Directional albedo E(μ) — {model_title(spec)}",
            xaxis=axis("μ = cos θ_v", range=[0, 1], dtick=0.1),
            yaxis=axis("E (fraction of energy reflected)", range=y_axis_range),
            annotations=annotations),
    }
