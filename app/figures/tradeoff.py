"""Error against cost, one curve per albedo method (log-log).

x: integrand evaluations or seconds; y: the largest |E − E_ref| over the cosines asked
for. Each method's own reported error (a bound for quadrature and table, one standard
error for Monte Carlo) is the dashed line of the same colour: where the solid curve
rises above it, the reported error was too small. The dotted grey line is the
reference's own bound: differences below it are not resolved.

The table does no integrand evaluation at lookup: against evaluations it is a
horizontal line (its error at any cost), against seconds one marker.
"""
from __future__ import annotations

import numpy as np

from .markup import subscripted
from .style import PALETTE, base_layout, log_axis, model_title

#: Decades the error axis spans at most (errors reach the rounding floor, 1e-16).
ERROR_DECADES = 17
X_LABELS = {"evaluations": "integrand evaluations (all μ, one run)",
            "seconds": "seconds (wall clock, one run)"}
REFERENCE_COLOUR = "#888888"
#: One colour per method whatever else is drawn (Okabe-Ito; the table black, apart from
#: the quadrature's blue).
COLOURS = {"quadrature": PALETTE[0], "mc_uniform": PALETTE[1], "mc_cosine": PALETTE[2],
           "mc_ndf": PALETTE[3], "mc_vndf": PALETTE[4], "table": PALETTE[6]}
#: How an error below the reference's bound is drawn: at the bound, an open triangle
#: pointing down, its hover saying so.
UNRESOLVED_SYMBOL = "triangle-down-open"
UNRESOLVED_TEXT = "(≤ reference bound: not resolved)"
#: Margin (decades) around the drawn points, so that none sits on the frame.
PAD_DECADES = 0.2


def _positive(values) -> list:
    """Values for a log axis: zero or a gap (NaN, null) is not drawn (None)."""
    return [float(v) if np.isfinite(v) and v > 0 else None
            for v in np.asarray(values, dtype=float)]


def _list(values) -> list:
    """Plain lists in the traces (they are short): figures/overlay.py finds a trace in
    a list by ==, which numpy arrays of different lengths cannot answer."""
    return np.asarray(values, dtype=float).tolist()


def _padded(ax: dict) -> dict:
    if "range" in ax:
        lo, hi = ax["range"]
        ax["range"] = [lo - PAD_DECADES, hi + PAD_DECADES]
    return ax


def _hover(method: str) -> str:
    return (f"{method} %{{text}}<br>budget=%{{customdata[0]}}<br>evaluations=%{{customdata[1]}}"
            "<br>seconds=%{customdata[2]:.3g}<br>error=%{customdata[3]:.3g}"
            "<br>reported=%{customdata[4]:.3g}<br>within reported at %{customdata[5]:.0%} of μ"
            "<extra></extra>")


@subscripted
def tradeoff_figure(data: dict, spec: dict, x: str = "evaluations") -> dict:
    methods = list(data.get("methods", []))
    per_point = np.asarray(data["method_index"], dtype=int)
    xs_all = np.asarray(data[x], dtype=float)
    drawn = xs_all[np.isfinite(xs_all) & (xs_all > 0)]
    span = [float(drawn.min()), float(drawn.max())] if drawn.size else [1.0, 10.0]
    ref = data.get("reference_error")
    floor = ref if ref is not None and ref > 0 else None
    traces, ys, any_unresolved = [], [], False
    for k, method in enumerate(methods):
        rows = per_point == k
        colour = COLOURS.get(method, PALETTE[k % len(PALETTE)])
        custom = np.stack([np.asarray(data[c], dtype=float)[rows] for c in
                           ("budget", "evaluations", "seconds", "error", "E_error",
                            "within_reported")], axis=-1)
        xv = xs_all[rows]
        err = np.asarray(data["error"], dtype=float)[rows]
        rep = np.asarray(data["E_error"], dtype=float)[rows]
        flat = rows.sum() == 1 and not (xv[0] > 0)      # the table against evaluations
        if flat:
            xv, err, rep, custom = (np.array(span), np.repeat(err, 2), np.repeat(rep, 2),
                                    np.repeat(custom, 2, axis=0))
        name = (f"{method} (0 evaluations at lookup)" if flat else method)
        # below the reference's own bound a difference is not resolved: drawn at the bound
        # as an open downward triangle ("≤ bound"), never at its unresolved value
        unresolved = (np.isfinite(err) & (err < floor)) if floor is not None else np.zeros(err.shape, bool)
        shown = np.where(unresolved, floor, err) if floor is not None else err
        common = {"type": "scatter", "x": _list(xv), "legendgroup": method,
                  "customdata": _list(custom),
                  "hovertemplate": _hover(method)}
        traces.append({**common, "mode": "lines" if flat else "lines+markers", "name": name,
                       "y": _positive(shown), "line": {"color": colour, "width": 2},
                       "marker": {"size": 7, "color": colour,
                                  "symbol": [UNRESOLVED_SYMBOL if u else "circle" for u in unresolved]},
                       "text": [UNRESOLVED_TEXT if u else "" for u in unresolved]})
        single = rows.sum() == 1 and not flat
        traces.append({**common, "mode": "markers" if single else "lines",
                       "name": f"{method}: reported error", "showlegend": False,
                       "y": _positive(rep), "line": {"color": colour, "width": 1.2, "dash": "dash"},
                       "marker": {"size": 9, "color": colour, "symbol": "circle-open"}})
        ys += [shown, rep]
        any_unresolved = any_unresolved or bool(unresolved.any())
    if ref is not None and ref > 0:
        traces.append({"type": "scatter", "mode": "lines", "x": span, "y": [ref, ref],
                       "name": "reference's error bound", "meta": {"role": "guide"},
                       "line": {"color": REFERENCE_COLOUR, "width": 1, "dash": "dot"},
                       "hovertemplate": "reference bound %{y:.2g}<extra></extra>"})
        ys.append([ref])
    # A legend entry for the dashes (the dashed traces themselves are grouped with
    # their method's entry, so one click hides both).
    traces.append({"type": "scatter", "mode": "lines", "x": [None], "y": [None],
                   "name": "dashed: the method's reported error", "meta": {"role": "guide"},
                   "line": {"color": "#444444", "width": 1.2, "dash": "dash"},
                   "hoverinfo": "skip"})
    if any_unresolved:
        traces.append({"type": "scatter", "mode": "markers", "x": [None], "y": [None],
                       "name": "▽ at the reference bound: error ≤ bound (not resolved)",
                       "meta": {"role": "guide"}, "hoverinfo": "skip",
                       "marker": {"symbol": UNRESOLVED_SYMBOL, "color": "#444444", "size": 8}})
    values = np.concatenate([np.ravel(np.asarray(v, dtype=float)) for v in ys]) if ys else []
    n_mu = data.get("mu_count")
    title = (f"Albedo error against {x} — {model_title(spec)}<br>"
             f"<sub>max over {n_mu} μ of |E − E_ref|; E_ref: quadrature, bound "
             f"{ref:.1g}; {data.get('timing', '')}</sub>") if ref is not None else \
        f"Albedo error against {x} — {model_title(spec)}"
    return {
        "data": traces,
        "layout": base_layout(
            title,
            xaxis=_padded(log_axis(X_LABELS[x], drawn, 12)),
            yaxis=_padded(log_axis("max over μ of |E − E_ref| (E dimensionless)", values,
                                   ERROR_DECADES)),
            margin={"l": 70, "r": 20, "t": 70, "b": 50},
            legend={"orientation": "h", "y": -0.2, "x": 0, "groupclick": "togglegroup"}),
    }
