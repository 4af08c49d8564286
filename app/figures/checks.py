"""The identity checks as a table: each identity, its computed value next to the value
it must have, the difference, the numerical error and whether it holds.

No physics here: the rows come from ``app.checks`` (columns: lists of equal length).
"""
from __future__ import annotations

import math

from .style import base_layout, model_title

#: Cell fills: light tints of the palette's blue (holds) and vermilion (does not hold),
#: grey where the row does not apply. The ✓/✗ glyphs carry the same information for
#: readers who do not tell the tints apart.
FILL_HOLDS, FILL_FAILS, FILL_NA = "#d6e8f5", "#f9dccc", "#eeeeee"
#: Column widths (relative) and header labels; the identity column needs the room.
COLUMNS = (("identity", 3.3), ("value", 1.25), ("expected", 1.25), ("difference", 1.05),
           ("error", 0.85), ("holds", 0.55))
#: Characters of a note shown under a row's identity when the row fails or does not apply
#: (the full note is in the data): enough for its first clause at 800 px.
NOTE_CHARS = 72


def _number(x, digits: int = 10) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    return f"{x:.{digits}g}"


def _small(x) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    return f"{x:.1e}"


def _short(note: str) -> str:
    """The note's first clause (app/checks.py puts the reason a row fails or does not
    apply there), cut to NOTE_CHARS."""
    first = note.split(";")[0]
    return first if len(first) <= NOTE_CHARS else first[:NOTE_CHARS - 1] + "…"


def checks_figure(data: dict, spec: dict) -> dict:
    rows = range(len(data["id"]))
    identity, value, expected, difference, error, holds, fill = [], [], [], [], [], [], []
    for i in rows:
        ok = data["holds"][i]
        text = f"<b>{data['id'][i]}</b>  {data['identity'][i]}"
        if ok is not True:
            text += f"<br><span style='font-size:10px;color:#555'>{_short(data['note'][i])}</span>"
        identity.append(text)
        value.append(_number(data["value"][i]))
        rel = data["relation"][i]
        expected.append(("" if rel == "=" else rel + " ") + _number(data["expected"][i]))
        difference.append(_small(data["difference"][i]))
        error.append(_small(data["error"][i]))
        holds.append("✓" if ok is True else "✗" if ok is False else "n/a")
        fill.append(FILL_HOLDS if ok is True else FILL_FAILS if ok is False else FILL_NA)
    cells = [identity, value, expected, difference, error, holds]
    title = (f"Identity checks — {model_title(spec)}, masking={spec['masking']}, g2={spec['g2']}"
             f"<br><span style='font-size:12px'>v at θ={data['theta_deg']:g}°, φ={data['phi_deg']:g}° "
             f"(μ={data['mu']:.4g}); holds: |difference| ≤ error + {data['hold_tolerance']:g}; "
             f"{data['total_evaluations']} evaluations, {data['total_seconds']:.3f} s</span>")
    return {
        "data": [{
            "type": "table",
            "columnwidth": [w for _, w in COLUMNS],
            "header": {"values": [f"<b>{name}</b>" for name, _ in COLUMNS],
                       "align": ["left"] + ["right"] * 4 + ["center"],
                       "fill": {"color": "#f2f2f2"}, "line": {"color": "#cccccc"},
                       "font": {"size": 12}, "height": 26},
            "cells": {"values": cells,
                      "align": ["left"] + ["right"] * 4 + ["center"],
                      "fill": {"color": [["white"] * len(fill)] * 5 + [fill]},
                      "line": {"color": "#dddddd"},
                      "font": {"size": [12, 12, 12, 12, 12, 15]}, "height": 30},
        }],
        "layout": base_layout(title, margin={"l": 20, "r": 20, "t": 70, "b": 20}),
    }
