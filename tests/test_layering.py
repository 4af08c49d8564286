"""Imports go one way, down the stack: api → views (with export, gallery, cli) →
analysis → model/quantities → integrate → kernels → physics. Figures import no physics
and nothing above them; nothing below the api imports it; nothing below the views
imports FastAPI or Plotly; nothing below the kernels imports numba.
"""
import ast
from pathlib import Path

import pytest

APP = Path(__file__).resolve().parents[1] / "app"


def imported_modules(path: Path) -> set[str]:
    tree = ast.parse(path.read_text(encoding="utf-8"))
    package = ".".join(path.relative_to(APP.parent).with_suffix("").parts[:-1])
    out = set()
    for node in ast.walk(tree):
        if isinstance(node, ast.Import):
            out.update(alias.name for alias in node.names)
        elif isinstance(node, ast.ImportFrom):
            if node.level:
                base = package.split(".")[: len(package.split(".")) - node.level + 1]
                out.add(".".join(base + ([node.module] if node.module else [])))
            else:
                out.add(node.module or "")
    return out


#: The stack, top to bottom: each layer may import those below it, none above.
STACK = [
    ("api", ("app.api", "app.main")),
    ("views", ("app.views", "app.export", "app.gallery", "app.cli")),
    ("analysis", ("app.analysis",)),
    ("model", ("app.model", "app.quantities", "app.adaptive")),
    ("integrate", ("app.integrate",)),
    ("kernels", ("app.kernels",)),
    ("physics", ("app.physics",)),
]
WEB = ("fastapi", "starlette")


def _modules(prefixes) -> list[Path]:
    out = []
    for prefix in prefixes:
        path = APP.parent / prefix.replace(".", "/")
        out += sorted(path.rglob("*.py")) if path.is_dir() else (
            [path.with_suffix(".py")] if path.with_suffix(".py").exists() else [])
    return out


def _banned(layer: str) -> tuple[str, ...]:
    """What a layer may not import: every layer above it, and HTTP below the views."""
    names = [n for n, _ in STACK]
    above = [p for n, prefixes in STACK[:names.index(layer)] for p in prefixes]
    if layer == "views":     # the exports, gallery and CLI sit beside the views, above them
        above = [p for p in above if p not in ("app.export",)]
    web = WEB if names.index(layer) > names.index("api") else ()
    plot = ("plotly",) if names.index(layer) > names.index("views") else ()
    # the physics states formulas in plain Python and numpy; app.kernels compiles them
    compiled = ("numba",) if names.index(layer) > names.index("kernels") else ()
    return (*above, *web, *plot, *compiled)


def _violations(files: list[Path], banned) -> list[str]:
    return [f"{path.relative_to(APP.parent)} imports {module}"
            for path in files for module in imported_modules(path)
            for b in banned if module == b or module.startswith(b + ".")]


@pytest.mark.parametrize("layer", [n for n, _ in STACK[1:]])
def test_the_stack_imports_downward_only(layer):
    prefixes = dict(STACK)[layer]
    files = _modules(prefixes)
    assert files, layer
    assert _violations(files, _banned(layer)) == []


def test_figures_import_no_physics_and_nothing_above_them():
    """Figures draw arrays: no physics, no integration. They may read app.model's
    registry (option labels and defaults, for titles)."""
    files = _modules(("app.figures",))
    assert files
    assert _violations(files, ("app.physics", "app.integrate", "app.kernels",
                               "app.quantities", "app.analysis", "app.views", "app.api",
                               "app.export", "fastapi", "starlette")) == []


def test_nothing_below_the_api_imports_it():
    files = [p for p in APP.rglob("*.py")
             if not p.is_relative_to(APP / "api") and p != APP / "main.py"]
    assert _violations(files, ("app.api",)) == []
