"""Imports go one way, down the ranks of docs' module map (GUIDE: api on top, physics and
figures at the bottom): every package of app/ has a rank, no module imports one ranked
above its own, and no modules import each other in a circle (late imports, inside a
function, count: a circle broken by one is still a circle). Below the API nothing imports
FastAPI; below the views nothing imports Plotly; below the kernels nothing imports numba.

What today's code still does against these rules is in KNOWN, each with the issue that
removes it; the tests fail on anything else, and on an entry of KNOWN that no longer
holds (so the list only shrinks).
"""
from __future__ import annotations

import ast
from pathlib import Path

import pytest

APP = Path(__file__).resolve().parents[1] / "app"

#: The ranks, top to bottom: a module may import its own rank and those below it.
RANKS = [
    ("wiring", ("app.main", "app.cli")),
    ("api", ("app.api", "app.server", "app.work")),
    ("export", ("app.export", "app.gallery")),
    ("views", ("app.views",)),
    ("analysis", ("app.analysis", "app.environment")),
    ("data", ("app.datasets", "app.fit", "app.lut")),
    # a model family's package (app/model/registry.py finds it) ranks with the registry
    ("model", ("app.model", "app.principled", "app.quantities", "app.adaptive", "app.materials")),
    ("integrate", ("app.integrate",)),
    ("kernels", ("app.kernels",)),
    ("shader", ("app.shader",)),
    ("physics", ("app.physics", "app.figures")),
    ("base", ("app.config", "app.errors", "app.resources", "app")),
]

#: Imports against the ranks or in a circle that today's code has, with the issue that
#: removes them. The lead empties this list as the branches that fix them are merged.
KNOWN = {
    # upward: "importer imports imported"
    "app.figures.titles imports app.model": "31: figures read the model registry's labels; pass them in",
    "app.shader.conventions imports app.integrate": "31: the conventions' check a view on integrate",
    "app.shader.conventions_figure imports app.model": "31: the conventions' figure built in figures/",
    "app.shader.embed imports app.integrate": "31: shader is dispatch only; tables embedded from below",
    "app.shader.generate imports app.integrate": "31: shader is dispatch only; spellings with the physics",
    "app.shader.generate imports app.model": "31: shader is dispatch only; spellings with the physics",
    # circles, each as its sorted modules
}


def _module_name(path: Path) -> str:
    parts = path.relative_to(APP.parent).with_suffix("").parts
    return ".".join(parts[:-1] if parts[-1] == "__init__" else parts)


MODULES = {_module_name(p): p for p in APP.rglob("*.py") if "_generated" not in p.parts}


def _resolve(name: str) -> str | None:
    """The module of app/ an imported name lives in (``app.x.y.f`` → ``app.x.y``)."""
    while name and name not in MODULES:
        name = name.rpartition(".")[0]
    return name or None


def imported_modules(path: Path) -> set[str]:
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
    return out


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


def test_every_package_of_app_has_a_rank():
    packages = {_package(m) for m in MODULES} - {"app"}
    assert sorted(p for p in packages if _rank(p) is None) == []


def _upward() -> set[str]:
    out = set()
    for module, imported in _graph().items():
        for other in imported:
            if _rank(other) < _rank(module):
                out.add(f"{module} imports {_package(other) if _rank(other) is not None else other}")
    return out


def _circles() -> list[list[str]]:
    """The strongly connected components of more than one module (Tarjan)."""
    graph, index, low, stack, on, out = _graph(), {}, {}, [], set(), []

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
    found = _upward()
    known = {k for k in KNOWN if not k.startswith("circle ")}
    assert sorted(found - known) == [], "imports above their own rank"
    assert sorted(known - found) == [], "fixed: take these out of KNOWN"


def test_no_import_circles():
    found = {"circle " + ", ".join(c) for c in _circles()}
    known = {k for k in KNOWN if k.startswith("circle ")}
    assert sorted(found - known) == [], "modules that import each other in a circle"
    assert sorted(known - found) == [], "fixed: take these out of KNOWN"


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
