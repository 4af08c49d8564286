"""Physics notation in figure text: an indexed symbol ("θ_v", "E_avg", "f_r") is written
with Plotly's subscript markup ("θ<sub>v</sub>"), which Plotly renders in titles, axis
and colourbar titles, legend names, annotations, hover templates and table cells, and
kaleido's SVG/PNG exports with them. An underscore is shown by Plotly as an underscore.

Only a symbol gets an index: ONE letter standing alone (not the end of a word) followed by
"_" and letters or digits up to the end of the word. API names stay names, underscores
and all: "theta_o_deg", "alpha_y=0.5", "mc_uniform", "height_correlated".

The builders here write plain "θ_v" (what the model's titles and the data's names say);
:func:`markup` converts a whole figure, applied by :func:`subscripted` to every builder
of this package and by ``figures.to_json`` to every figure served as JSON (those built
elsewhere too). It is idempotent: converted text has no underscore left to convert.
"""
from __future__ import annotations

import functools
import re

#: a symbol (one Latin or Greek letter, not preceded by a letter, digit, "_", "{", "%" or
#: ".") + "_" + its index (letters or digits, the whole rest of the word)
INDEXED = re.compile(r"(?<![\w{%.])([A-Za-zα-ωΑ-Ωϑϕϵ])_([A-Za-z0-9]+)(?!\w)")

#: keys whose string value is text a reader sees (trace names, hover templates, titles,
#: annotation texts); "title" given as a bare string too
_TEXT_KEYS = frozenset({"text", "name", "hovertemplate", "title"})
#: a table's header and cells hold their texts in "values" (a list of columns)
_TABLE_PARTS = frozenset({"header", "cells"})


def subscripts(text: str) -> str:
    """"D(θ_m)·cos θ_m" → "D(θ<sub>m</sub>)·cos θ<sub>m</sub>"; "E_avg = 0.05" →
    "E<sub>avg</sub> = 0.05"; "theta_o_deg", "mc_uniform" unchanged."""
    return INDEXED.sub(r"\1<sub>\2</sub>", text) if "_" in text else text


def _strings(values):
    """A table's values: strings converted, lists of them recursively, numbers kept."""
    if isinstance(values, str):
        return subscripts(values)
    if isinstance(values, (list, tuple)):
        return [_strings(v) for v in values]
    return values


def _node(node: dict, table: bool = False) -> dict:
    out = {}
    for key, value in node.items():
        if isinstance(value, str) and key in _TEXT_KEYS:
            out[key] = subscripts(value)
        elif isinstance(value, dict):
            out[key] = _node(value, table=key in _TABLE_PARTS)
        elif key == "annotations" and isinstance(value, (list, tuple)):
            out[key] = [_node(a) if isinstance(a, dict) else a for a in value]
        elif table and key == "values" and isinstance(value, (list, tuple)):
            out[key] = _strings(value)
        else:
            out[key] = value            # arrays and numbers: the same objects, not copied
    return out


def markup(figure: dict) -> dict:
    """A copy of ``figure`` (dicts copied where text may be, arrays shared) with
    :func:`subscripts` applied to its layout's titles and annotations, its traces' names,
    hover templates and colourbar titles, and its tables' texts."""
    out = dict(figure)
    if isinstance(figure.get("data"), (list, tuple)):
        out["data"] = [_node(t) if isinstance(t, dict) else t for t in figure["data"]]
    if isinstance(figure.get("layout"), dict):
        out["layout"] = _node(figure["layout"])
    return out


def subscripted(builder):
    """A figure builder whose figure comes out with :func:`markup` applied."""
    @functools.wraps(builder)
    def build(*args, **kwargs):
        return markup(builder(*args, **kwargs))
    return build
