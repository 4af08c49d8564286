"""The page's modules import one another without a circle (issue 31: state.js and pins.js
imported each other, a circle broken by a late namespace import)."""
from __future__ import annotations

import re
from pathlib import Path

STATIC_JS = Path(__file__).resolve().parents[2] / "static" / "js"
IMPORT = re.compile(r'^\s*import\b[^"\']*["\'](\.{1,2}/[^"\']+)["\']', re.M)


def imports() -> dict[Path, set[Path]]:
    graph = {}
    for path in STATIC_JS.rglob("*.js"):
        graph[path] = {(path.parent / m).resolve() for m in IMPORT.findall(path.read_text(encoding="utf-8"))}
    return graph


def test_every_relative_import_names_a_file():
    missing = [(p.name, str(t)) for p, ts in imports().items() for t in ts if not t.exists()]
    assert not missing


def test_no_import_circle():
    graph = imports()
    circles = []

    def visit(node, trail):
        for nxt in graph.get(node, ()):
            if nxt in trail:
                circles.append([p.name for p in trail[trail.index(nxt):]] + [nxt.name])
            elif nxt not in done:
                visit(nxt, trail + [nxt])
        done.add(node)

    done: set[Path] = set()
    for start in graph:
        if start not in done:
            visit(start, [start])
    assert not circles, circles
