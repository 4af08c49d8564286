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


def test_every_format_of_every_view_is_one_documented_operation(client):
    """/docs shows the figure formats as one operation with a ``format`` parameter (issue
    34: ~75 format twins came first among 147 operations); the twins still answer."""
    from app.views import VIEWS
    paths = client.get("/openapi.json").json()["paths"]
    assert [p for p in paths if p.startswith("/api/v1/figures/") and "." in p.rsplit("/", 1)[1]
            and p != "/api/v1/figures/{view}.{format}"] == []
    op = paths["/api/v1/figures/{view}.{format}"]["get"]
    params = {p["name"]: p for p in op["parameters"]}
    assert params["format"]["schema"]["enum"] == ["svg", "png", "csv", "json"]
    assert params["view"]["schema"]["enum"] == list(VIEWS)
    assert {"width", "height", "scale"} <= set(params) and "503" in op["responses"]
    for kind in VIEWS:
        assert {"vary", "values"} <= {p["name"] for p in paths[f"/api/v1/figures/{kind}"]["get"]["parameters"]}
    assert sum(len(item) for item in paths.values()) < 100
    assert "/embed/{kind}" in paths and "/gallery" in paths and "/api/v1/views" in paths
    for ext in ("svg", "csv", "json"):                     # the old URLs keep working
        r = client.get(f"/api/v1/figures/ndf.{ext}?alpha=0.2&width=200&height=200" if ext == "svg"
                       else f"/api/v1/figures/ndf.{ext}?alpha=0.2")
        assert r.status_code in ((200, 503) if ext == "svg" else (200,))


def test_docs_are_grouped_by_task_with_the_numbers_first(client):
    """Tags in task order, /eval first of the numbers, /albedo and /datasets near the top."""
    spec = client.get("/openapi.json").json()
    tags = [t["name"] for t in spec["tags"]]
    assert tags[:3] == ["data", "figures", "datasets"]
    data = [p for p, item in spec["paths"].items() for op in item.values() if "data" in op.get("tags", [])]
    assert data[0] == "/api/v1/eval" and "/api/v1/albedo" in data
    assert "/api/v1/datasets" in spec["paths"]
    assert all(op.get("tags") for item in spec["paths"].values() for op in item.values())
