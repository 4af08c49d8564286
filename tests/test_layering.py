"""Imports go one way: physics ← integrate ← (quantities, model) ← figures/api.

physics/ and integrate/ import neither FastAPI nor Plotly; physics/ does not import
integrate/; figures/ does no physics (imports nothing from physics/ or integrate/).
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


RULES = {
    "physics": ("fastapi", "starlette", "plotly", "app.integrate", "app.api", "app.figures",
                "app.model", "app.quantities"),
    "integrate": ("fastapi", "starlette", "plotly", "app.api", "app.figures"),
    "figures": ("fastapi", "app.physics", "app.integrate"),
}


@pytest.mark.parametrize("layer", sorted(RULES))
def test_import_direction(layer):
    files = sorted((APP / layer).rglob("*.py"))
    assert files
    for path in files:
        for module in imported_modules(path):
            for banned in RULES[layer]:
                assert not (module == banned or module.startswith(banned + ".")), \
                    f"{path.relative_to(APP.parent)} imports {module}"
