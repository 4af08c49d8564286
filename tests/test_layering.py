"""Imports go one way, down the ranks of docs/architecture.md's module map (wiring and
the API on top, physics and the base at the bottom): every package and top-level module
of app/ is named in exactly one rank, and so is every folder of static/js/; a module imports only modules of its own rank or
below ("upward" is an import of a module ranked above the importer's), and no modules
import each other in a circle (late imports, inside a function, count: a circle broken
by one is still a circle). Below the API nothing imports FastAPI; below the views nothing
but figures/ imports Plotly; below the kernels nothing imports numba.
"""
from __future__ import annotations

import ast
import re
import sys
from functools import lru_cache
from pathlib import Path

import pytest

APP = Path(__file__).resolve().parents[1] / "app"

#: The ranks, top to bottom: a module may import its own rank and those below it. A
#: name ranks all modules under it, unless a longer name ranks one of them elsewhere.
RANKS = [
    ("wiring", ("app.main", "app.cli")),
    ("api", ("app.api", "app.server", "app.work")),
    ("export", ("app.export", "app.gallery")),
    ("views", ("app.views",)),
    # arrays → Plotly dicts, no physics (the PNG of a rendered image: app.lut.png)
    ("figures", ("app.figures",)),
    ("analysis", ("app.analysis",)),
    ("data", ("app.datasets", "app.fit", "app.lut")),
    # the lit sphere: one renderer for point lights and environments
    ("rendering", ("app.environment",)),
    ("quantities", ("app.quantities", "app.adaptive")),
    # code for a configured model (and the ecosystems' roughness conventions)
    ("shader", ("app.shader",)),
    # a model family's package (app/model/registry.py finds it) ranks with the registry;
    # what a title says about a model reads the registry's labels
    ("model", ("app.model", "app.principled", "app.materials", "app.figures.titles")),
    ("integrate", ("app.integrate",)),
    ("kernels", ("app.kernels",)),
    ("physics", ("app.physics",)),
    ("base", ("app.config", "app.errors", "app.resources", "app.allocator", "app.npz", "app")),
]


def _module_name(path: Path) -> str:
    parts = path.relative_to(APP.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(p): p for p in APP.rglob("*.py")}


def _resolve(name: str) -> str | None:
    """The module of app/ an imported name lives in (``app.x.y.f`` → ``app.x.y``)."""
    while name and name not in MODULES:
        name = name.rpartition(".")[0]
    return name or None


@lru_cache(maxsize=None)
def imported_modules(path: Path) -> frozenset[str]:
    """Every name the file imports, anywhere in it, absolute; ``from m import n`` gives
    ``m.n`` when that is a module, else ``m``."""
    name = _module_name(path)
    package = name if path.name == "__init__.py" else name.rpartition(".")[0]
    out = set()
    for node in ast.walk(ast.parse(path.read_text(encoding="utf-8"))):
        if isinstance(node, ast.Import):
            out.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                parts = package.split(".")
                base = ".".join(parts[:len(parts) - node.level + 1] + ([node.module] if node.module else []))
            else:
                base = node.module or ""
            for alias in node.names:
                out.add(f"{base}.{alias.name}" if f"{base}.{alias.name}" in MODULES else base)
    return frozenset(out)


def _graph() -> dict[str, set[str]]:
    out = {}
    for name, path in MODULES.items():
        found = {_resolve(m) for m in imported_modules(path) if m == "app" or m.startswith("app.")}
        out[name] = {m for m in found if m and m != name and m != "app"}
    return out


def _rank(module: str) -> int | None:
    best = None
    for k, (_, prefixes) in enumerate(RANKS):
        for p in prefixes:
            if (module == p or module.startswith(p + ".")) and p != "app":
                if best is None or len(p) > best[1]:
                    best = (k, len(p))
    if best is None and module == "app":
        return len(RANKS) - 1
    return None if best is None else best[0]


def _package(module: str) -> str:
    return ".".join(module.split(".")[:2])


def test_every_package_of_app_is_named_in_one_rank():
    """The ranks name each package and top-level module of app/ (a new one is placed on
    the map before it is imported), and nothing that no longer exists."""
    tops = {_package(m) for m in MODULES} - {"app"}
    named = [p for _, prefixes in RANKS for p in prefixes if p.count(".") == 1]
    assert sorted(tops - set(named)) == [], "not on the map: give them a rank"
    assert sorted(set(named) - tops) == [], "on the map but not in app/"
    assert len(named) == len(set(named)), "named in two ranks"
    deeper = [p for _, prefixes in RANKS for p in prefixes if p.count(".") > 1]
    assert [p for p in deeper if p not in MODULES] == []


def _upward() -> set[str]:
    out = set()
    for module, imported in _graph().items():
        for other in imported:
            if _rank(other) < _rank(module):
                out.add(f"{module} imports {_package(other) if _rank(other) is not None else other}")
    return out


def _circles(graph: dict[str, set[str]] | None = None) -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan) of ``graph``
    (app/'s import graph when None)."""
    graph = _graph() if graph is None else graph
    index, low, stack, on, out = {}, {}, [], set(), []

    def visit(v):
        index[v] = low[v] = len(index)
        stack.append(v)
        on.add(v)
        for w in graph[v]:
            if w not in index:
                visit(w)
                low[v] = min(low[v], low[w])
            elif w in on:
                low[v] = min(low[v], index[w])
        if low[v] == index[v]:
            component = []
            while True:
                w = stack.pop()
                on.discard(w)
                component.append(w)
                if w == v:
                    break
            if len(component) > 1:
                out.append(sorted(component))
    for v in sorted(graph):
        if v not in index:
            visit(v)
    return out


def test_no_module_imports_upward():
    assert sorted(_upward()) == [], "imports of a module ranked above the importer"


def test_no_import_circles():
    assert _circles() == [], "modules that import each other in a circle"


def test_the_checks_see_an_upward_import_and_a_circle(monkeypatch):
    """The two checks above on a graph made to break them: physics importing the views
    is upward; two modules importing each other are a circle."""
    graph = {**_graph(), "app.physics.brdf": {"app.views.lobe"}, "app.views.lobe": {"app.physics.brdf"}}
    monkeypatch.setattr(sys.modules[__name__], "_graph", lambda: graph)
    assert "app.physics.brdf imports app.views" in _upward()
    assert ["app.physics.brdf", "app.views.lobe"] in _circles()


def _violations(prefixes, banned) -> list[str]:
    files = [p for name, p in MODULES.items()
             if any(name == x or name.startswith(x + ".") for x in prefixes)]
    assert files, prefixes
    return [f"{_module_name(p)} imports {m}" for p in files for m in imported_modules(p)
            for b in banned if m == b or m.startswith(b + ".")]


def _below(rank: str) -> tuple[str, ...]:
    names = [n for n, _ in RANKS]
    return tuple(p for _, prefixes in RANKS[names.index(rank) + 1:] for p in prefixes if p != "app")


@pytest.mark.parametrize("rank, banned", [("api", ("fastapi", "starlette")),
                                          ("views", ("plotly",)), ("kernels", ("numba",))])
def test_what_a_lower_rank_does_not_import(rank, banned):
    """HTTP only in the API and above, Plotly only in the views and above (figures build
    plain dicts), numba only in the kernels."""
    allowed = {"app.figures": ("plotly",)}       # figures/ builds and encodes Plotly JSON
    prefixes = [p for p in _below(rank) if not set(banned) & set(allowed.get(p, ()))]
    assert _violations(prefixes, banned) == []


def test_nothing_below_the_api_imports_it():
    below = [p for p in _below("api")] + [p for p in ("app.export", "app.gallery")]
    assert _violations(below, ("app.api", "app.main", "app.cli")) == []


STATIC_JS = APP.parent / "static" / "js"

#: static/js/'s folders, bottom to top (docs/architecture.md): a script imports from its own
#: folder or a lower rank; the folders of one rank (the entry points of the explorer and of
#: the other pages) import nothing of each other.
JS_RANKS = [("base",), ("chart", "net"), ("state",), ("controls",), ("panels",), ("gpu",), ("app", "pages")]
_JS_RANK = {folder: i for i, folders in enumerate(JS_RANKS) for folder in folders}
#: a relative module specifier: import … from "./x.js", import("../y/z.js"), new URL("./w.js", …)
_JS_IMPORT = re.compile(r"""(?:\bfrom\s*|\bimport\s*\(?\s*|new URL\(\s*)["'](\.{1,2}/[^"']+\.js)["']""")


def _js_graph() -> dict[str, set[str]]:
    """static/js's scripts (paths relative to it) → the scripts each imports."""
    graph = {}
    for path in STATIC_JS.rglob("*.js"):
        name = path.relative_to(STATIC_JS).as_posix()
        graph[name] = {(path.parent / spec).resolve().relative_to(STATIC_JS).as_posix()
                       for spec in _JS_IMPORT.findall(path.read_text())}
    return graph


def _js_wrong_way(graph: dict[str, set[str]]) -> set[str]:
    """Imports of a higher rank's script, or of another folder of the same rank."""
    out = set()
    for script, imported in graph.items():
        here = script.split("/")[0]
        for other in imported:
            there = other.split("/")[0]
            if there != here and _JS_RANK.get(there, -1) >= _JS_RANK.get(here, -1):
                out.add(f"{script} imports {other}")
    return out


def test_every_script_of_static_js_is_in_a_ranked_folder():
    graph = _js_graph()
    assert sorted(s for s in graph if s.split("/")[0] not in _JS_RANK or "/" not in s) == []
    assert sorted(f for f in _JS_RANK if not (STATIC_JS / f).is_dir()) == []
    assert all(t in graph for targets in graph.values() for t in targets), "an import of a missing script"


def test_no_script_imports_upward_or_across_and_none_in_a_circle():
    graph = _js_graph()
    assert sorted(_js_wrong_way(graph)) == []
    assert _circles(graph) == []


def test_the_script_checks_see_an_upward_import_and_a_circle():
    graph = {**_js_graph(), "base/dom.js": {"panels/panels.js"}, "pages/lut.js": {"app/main.js"}}
    wrong = _js_wrong_way(graph)
    assert "base/dom.js imports panels/panels.js" in wrong and "pages/lut.js imports app/main.js" in wrong
    assert any("base/dom.js" in c for c in _circles(graph))
