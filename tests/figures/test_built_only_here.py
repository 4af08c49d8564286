"""Every Plotly figure of the product is built in app/figures/ (issue 31: one way to
draw): no module elsewhere writes a figure dict — a literal with both "data" and
"layout" keys — except as an OpenAPI example (a value under "example"/"examples")."""
from __future__ import annotations

import ast
from pathlib import Path

APP = Path(__file__).resolve().parents[2] / "app"
FIGURES = APP / "figures"


def _figure_literals(tree: ast.AST) -> list[int]:
    """Line numbers of dict literals with "data" and "layout" keys, not inside an example."""
    found, todo = [], [tree]
    while todo:
        node = todo.pop()
        if isinstance(node, ast.Dict):
            keys = {k.value for k in node.keys if isinstance(k, ast.Constant)}
            if {"data", "layout"} <= keys:
                found.append(node.lineno)
            todo += [v for k, v in zip(node.keys, node.values)
                     if not (isinstance(k, ast.Constant) and k.value in ("example", "examples"))]
            todo += [k for k in node.keys if k is not None]
        else:
            todo += list(ast.iter_child_nodes(node))
    return found


def test_the_check_sees_a_figure_and_skips_an_example():
    code = 'a = {"data": [], "layout": {}}\nb = {"example": {"data": [], "layout": {}}}\n'
    assert _figure_literals(ast.parse(code)) == [1]


def test_figures_are_built_only_in_app_figures():
    outside = [f"{p.relative_to(APP.parent)}:{line}" for p in sorted(APP.rglob("*.py"))
               if FIGURES not in p.parents
               for line in _figure_literals(ast.parse(p.read_text(encoding="utf-8")))]
    assert outside == []
