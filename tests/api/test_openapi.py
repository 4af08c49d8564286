"""/docs: every endpoint shows an example (of its parameters or of its answer)."""
from __future__ import annotations


def _has_example(node) -> bool:
    if isinstance(node, dict):
        if node.get("example") is not None or node.get("examples"):
            return True
        return any(_has_example(v) for v in node.values())
    if isinstance(node, list):
        return any(_has_example(v) for v in node)
    return False


def test_every_endpoint_has_an_example(client):
    spec = client.get("/openapi.json").json()
    missing = []
    for path, ops in spec["paths"].items():
        for method, op in ops.items():
            body = op.get("requestBody", {})
            if not (_has_example(op.get("parameters", [])) or _has_example(op.get("responses", {}))
                    or _has_example(body)):
                missing.append(f"{method.upper()} {path}")
    assert missing == []


def test_export_routes_are_documented_for_every_view(client):
    from app.views import VIEWS
    paths = client.get("/openapi.json").json()["paths"]
    for kind in VIEWS:
        for ext in ("svg", "png", "csv", "json"):
            op = paths[f"/api/v1/figures/{kind}.{ext}"]["get"]
            names = {p["name"] for p in op["parameters"]}
            assert {"vary", "values"} <= names
            if ext in ("svg", "png"):
                assert {"width", "height", "scale"} <= names and "503" in op["responses"]
    assert "/embed/{kind}" in paths and "/gallery" in paths and "/api/v1/views" in paths
