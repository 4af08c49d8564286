"""The identity checks as a table: each identity, its computed value next to the value
it must have, the difference, the numerical error and whether it holds.

No physics here: the rows come from ``app.analysis.checks`` (columns: lists of equal length).
"""
from __future__ import annotations

import math

from .markup import subscripted
from .style import base_layout, model_title
from .titles import option_label

#: Cell fills: light tints of the palette's blue (holds) and vermilion (does not hold),
#: grey where the row does not apply. The ✓/✗ glyphs carry the same information for
#: readers who do not tell the tints apart.
FILL_HOLDS, FILL_FAILS, FILL_NA = "#d6e8f5", "#f9dccc", "#eeeeee"
#: Column widths (relative) and header labels; the identity column needs the room.
COLUMNS = (("identity", 3.0), ("value", 1.2), ("expected", 1.3), ("difference", 1.05),
           ("error", 0.9), ("holds", 0.55))
#: A note shown under a row's identity when the row fails or does not apply (the full
#: note is in the data): its first clause, in lines of NOTE_LINE characters (Plotly's
#: table cells do not wrap; 44 fit the identity column at 800 px and in a half-width
#: panel at 1280), at most NOTE_LINES lines.
NOTE_LINE, NOTE_LINES = 44, 2
#: Significant digits of value and expected (the data carry all 17; the difference and
#: error columns show the disagreement): 7 fit their column in a half-width panel.
DIGITS = 7


def _number(x, digits: int = DIGITS) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    return f"{x:.{digits}g}"


def _small(x) -> str:
    if x is None or (isinstance(x, float) and not math.isfinite(x)):
        return "—"
    return f"{x:.1e}"


def _short(note: str) -> str:
    """The note's first clause (app/checks.py puts the reason a row fails or does not
    apply there), wrapped at word boundaries into NOTE_LINES lines at most."""
    lines, line = [], ""
    for word in note.split(";")[0].split():
        if line and len(line) + 1 + len(word) > NOTE_LINE:
            lines.append(line)
            line = word
        else:
            line = f"{line} {word}".strip()
    lines.append(line)
    if len(lines) > NOTE_LINES:
        lines = lines[:NOTE_LINES]
        lines[-1] = lines[-1][:NOTE_LINE - 1] + "…"
    return "<br>".join(lines)


def _identity(text: str) -> str:
    """The identity, its parenthesis (the conditions) on a line of its own."""
    head, sep, tail = text.partition("  (")
    return f"{head}<br>({tail}" if sep else text


@subscripted
def checks_figure(data: dict, spec: dict) -> dict:
    rows = range(len(data["id"]))
    identity, value, expected, difference, error, holds, fill = [], [], [], [], [], [], []
    for i in rows:
        ok = data["holds"][i]
        text = f"<b>{data['id'][i]}</b>  {_identity(data['identity'][i])}"
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
    title = (f"Identity checks — {model_title(spec)} (Λ {option_label('masking', spec['masking'])}, "
             f"G2 {option_label('g2', spec['g2']).lower()})"
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
                      "font": {"size": [12, 11, 11, 11, 11, 15]}, "height": 28},
        }],
        "layout": base_layout(title, margin={"l": 20, "r": 20, "t": 64, "b": 20}),
    }
