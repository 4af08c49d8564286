"""The advice as a table: one row per choice (the current model first) with its largest
albedo error over the scene's range, its measured relative cost and whether it is within
tol; the recommended row highlighted (and the recommended albedo method, when rated)."""
from __future__ import annotations

from .markup import subscripted
from .style import base_layout
from .titles import option_text

#: The options named in the title's "cheaper choices than …".
_MODEL_OPTIONS = ("ndf", "masking", "g2", "fresnel")

#: Row fills: the recommended model, the recommended albedo method, every other row.
RECOMMENDED_FILL = "#CDEBDD"      # light tint of PALETTE[2] (bluish green)
METHOD_FILL = "#D6E9F5"           # light tint of PALETTE[5] (sky blue)
PLAIN_FILL = "white"
HEADER_FILL = "#EEEEEE"
#: Pixels per row and for the header: 16 rows fit a 560-pixel export under the title.
ROW_HEIGHT = 24


#: Differences at or below this are rounding, not an error: E and f are O(1) doubles
#: summed over at most a few thousand nodes (≈ 1e3 × 2.2e-16).
ROUNDING = 1e-12


def error_phrase(what: str, measured: float | None, bound: float) -> str:
    """The heading's "(albedo error 0.003 measured, ≤ 0.01 bound)" saying something true
    when there is nothing to measure: "albedo error 0 measured, ≤ 0 bound" read as a
    claim of perfection; below rounding it is "none beyond rounding" or "< 1e-12"."""
    if bound <= ROUNDING:
        return f"{what}: none beyond rounding (≤ {ROUNDING:.0e})"
    shown = f"< {ROUNDING:.0e}" if measured is None or measured <= ROUNDING else f"{measured:.2g}"
    return f"{what} {shown} measured, ≤ {bound:.2g} bound"


def _number(x, fmt: str) -> str:
    return "—" if x is None else format(x, fmt)


def _recommended(row: dict, data: dict) -> bool:
    return row.get("kind") in ("single", "combination") and row["changes"] == data["changes"]


def _method_chosen(row: dict, data: dict) -> bool:
    m = data.get("albedo_method")
    return (row.get("kind") == "albedo_method" and m is not None
            and row["changes"]["albedo_method"] == m["method"]
            and row["changes"].get("samples") == m.get("samples"))


def _model_name(spec: dict) -> str:
    """The model as people name it: "GGX, Λ Smith, G2 height-correlated, F Schlick"."""
    return ", ".join([option_text(option, spec[option]) for option in _MODEL_OPTIONS]
                     + (["Kulla-Conty"] if spec.get("multiscatter") == "kulla_conty" else []))


def _choice_name(changes: dict) -> str:
    """A row's changes by their labels ("Λ Karis, F Schlick"); a value that is not a
    registry choice (an albedo method, a sample count) as name and value."""
    out = []
    for option, value in changes.items():
        if option == "multiscatter" and value == "none":
            out.append("no Kulla-Conty")
            continue
        try:
            out.append(option_text(option, value))
        except KeyError:
            out.append(f"{option.replace('_', ' ')} {value}")
    return ", ".join(out)


@subscripted
def advise_figure(data: dict, spec: dict) -> dict:
    current = {"label": "current model", "max_error": 0.0, "relative_cost": 1.0,
               "within_tol": True, "kind": "current", "changes": {}}
    rows = [current] + list(data["alternatives"])
    fills = []
    for row in rows:
        chosen = (row is current and not data["changes"]) or _recommended(row, data)
        fills.append(RECOMMENDED_FILL if chosen else METHOD_FILL if _method_chosen(row, data)
                     else PLAIN_FILL)
    where = [("—" if r.get("worst_alpha") is None else
              f"α={r['worst_alpha']:.3g}, θ={r['worst_theta_deg']:.0f}°") for r in rows]
    kinds = {"current": "reference", "single": "model", "combination": "model (combined)",
             "albedo_method": "albedo method"}
    columns = [
        [r["label"] if r is current else _choice_name(r["changes"]) for r in rows],
        [kinds.get(r.get("kind"), "") for r in rows],
        [_number(r.get("max_difference"), ".2g") for r in rows],
        [_number(r["max_error"], ".2g") for r in rows],
        [_number(r["relative_cost"], ".3g") + ("" if r["relative_cost"] is None else "×") for r in rows],
        ["—" if r["max_error"] is None else "✓" if r["within_tol"] else "✗" for r in rows],
        where,
    ]
    pointwise = data.get("metric") == "pointwise"
    measured = "max |Δf|/f measured" if pointwise else "max |ΔE| measured"
    rng = data["range"]
    rec = data["changes"]
    said = _choice_name(rec) if rec else "keep the current model"
    method = data.get("albedo_method")
    if method is not None:
        said += f"; albedo by {method['method']}" + (f" ({method['samples']} samples)"
                                                      if method.get("samples") else "")
    model = _model_name(spec)
    # the recommendation first: a page heading shows the title's first lines only
    what = "relative error of f" if pointwise else "albedo error"
    title = (f"Recommended: {said} ({error_phrase(what, data.get('max_difference', data['max_error']), data['max_error'])}, "
             f"cost {data['relative_cost']:.3g}×)"
             + ("" if data.get("complete", True) else " — incomplete (time budget)")
             + f"<br>Cheaper choices than {model} over α ∈ [{rng['alpha_min']:g}, "
             f"{rng['alpha_max']:g}], θ ≤ {rng['theta_max_deg']:g}°, tol {data['tol']:g}")
    table = {
        "type": "table",
        "columnwidth": [3.0, 1.5, 1.2, 1.0, 1.1, 0.7, 1.7],
        "header": {"values": ["choice", "kind", measured, "bound", "relative cost", "≤ tol",
                              "largest at"],
                   "fill": {"color": HEADER_FILL}, "align": "left", "height": ROW_HEIGHT,
                   "font": {"size": 12}},
        "cells": {"values": columns, "fill": {"color": [fills] * len(columns)}, "align": "left",
                  "height": ROW_HEIGHT, "font": {"size": 12}},
    }
    layout = base_layout(title, margin={"l": 20, "r": 20, "t": 80, "b": 20})
    layout["annotations"] = [{
        "text": ((f"measured: the largest relative error of f at the nodes (floor "
                  f"{data.get('f_floor', 0.0):.2g}/sr for f near zero); bound: a safety factor "
                  "times it, what tol is checked against") if pointwise else
                 "measured: the largest |ΔE| of the directional albedo E(μ) at the nodes; bound: "
                 "what holds over the whole range (≤ 1), what tol is checked against")
                + "; cost: CPU time of f (models) or of E (albedo methods) over the current",
        "xref": "paper", "yref": "paper", "x": 0, "y": 0, "yanchor": "top", "showarrow": False,
        "font": {"size": 10, "color": "#555"}}]
    return {"data": [table], "layout": layout}
