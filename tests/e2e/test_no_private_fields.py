"""No module of the page reads a charting library's private fields (issue 31: one draw
path per panel, "no private fields of a charting library read anywhere in static/").

Plotly keeps its laid-out state in underscore fields (`gd._fullLayout`, `_fullData`,
`_context`, an axis's `_offset`, a polar subplot's `_subplot`) and its coordinate maps
(`c2p`, `p2c`, `c2g`) and calcdata on the SVG nodes (`node.__data__`); none of them is
API and any release may change them. The page reads the public figure (gd.data,
gd.layout, into which Plotly writes back the ranges and types it chose) and the SVG it
drew. An underscore field of the page's own is a WeakMap or a dataset entry instead, so
that the search needs no exceptions. The vendored library itself is not searched.
"""
from __future__ import annotations

import re
from pathlib import Path

STATIC = Path(__file__).resolve().parents[2] / "static"
#: a read of a field whose name starts with one underscore (`x._fullLayout`, `x["_context"]`),
#: d3's node data, Plotly's coordinate maps and calcdata
PRIVATE = re.compile(r"""\.\s*_(?!_)\w|\[\s*["']_(?!_)\w|__data__|\b(?:c2p|p2c|c2g|l2p|p2l|calcdata)\b""")


def private_reads() -> list[str]:
    found = []
    for path in sorted(STATIC.rglob("*")):
        if path.suffix not in (".js", ".html") or "vendor" in path.parts:
            continue
        for n, line in enumerate(path.read_text(encoding="utf-8").splitlines(), 1):
            code = line.split("//")[0] if not line.lstrip().startswith("*") else ""
            if PRIVATE.search(code):
                found.append(f"{path.relative_to(STATIC)}:{n}: {line.strip()}")
    return found


def test_no_private_field_of_a_charting_library_is_read():
    assert private_reads() == []


def test_the_search_finds_what_it_looks_for():
    """The pattern itself catches each form it is meant to (else the test above cannot fail)."""
    for bad in ("const fl = gd._fullLayout;", "div._context.staticPlot", 'gd["_fullData"]',
                "g.__data__[0].trace", "xa.c2p(x)", "ra.c2g(r)", "ax.p2c(px)"):
        assert PRIVATE.search(bad), bad
    for fine in ("gd.layout.xaxis.range", "window.__brdf.url(name)", "const a_b = 1;", "x.data"):
        assert not PRIVATE.search(fine), fine
