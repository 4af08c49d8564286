"""The request guard's index of operations is read off the routes (app/api/openapi.py:
FastAPI's own document takes seconds to build, and the server did not accept until it
was done). It must say exactly what the document says about every operation: its
parameters, which are lists and which are numbers, its request body's media types and
body limit, the methods of each path, and the names that are numbers in a JSON body."""
from __future__ import annotations

import fastapi.applications
import fastapi.openapi.utils

from app.api import openapi
from app.api.http import strict


def _is_array(schema: dict) -> bool:
    return any(v.get("type") == "array"
               for v in [schema, *schema.get("anyOf", []), *schema.get("oneOf", [])])


def _facts(op: dict) -> dict:
    params = op.get("parameters", [])
    return {
        "params": sorted((p["in"], p["name"]) for p in params),
        "lists": sorted(p["name"] for p in params
                        if p["in"] == "query" and _is_array(p.get("schema", {}))),
        "numbers": sorted(p["name"] for p in params if strict._is_numeric(p.get("schema", {}))),
        "body": sorted((op.get("requestBody") or {}).get("content", {})),
        "body_limit": op.get("x-body-limit"),
    }


def test_the_route_index_says_what_the_openapi_document_says(client):
    app = client.app
    document = client.get("/openapi.json").json()
    index = openapi.route_document(app)
    # the format twins (/figures/lobe.svg) are in the index only; the document shows them
    # as one operation, /figures/{view}.{format}, which no route of its own answers
    twins = {p for p, item in index["paths"].items() if item.get("get", {}).get("x-format-twin")}
    shown = {p for p in document["paths"] if p != "/api/v1/figures/{view}.{format}"}
    assert sorted(set(index["paths"]) - twins) == sorted(shown)
    for path, item in document["paths"].items():
        if path not in shown:
            continue
        assert sorted(index["paths"][path]) == sorted(item), path
        for method, op in item.items():
            assert _facts(index["paths"][path][method]) == _facts(op), f"{method.upper()} {path}"
    assert strict.numeric_names(index) == strict.numeric_names(document)


def test_the_index_is_what_the_guard_reads_and_builds_no_document(client, monkeypatch):
    from app.main import create_app
    from tests.budget import settings_for_tests
    app = create_app(settings_for_tests())
    # FastAPI's generator (1-9 s, and the server did not accept until it was done) must
    # not run: it is made to fail here, and a call to it would raise out of operations().
    def no_document(*args, **kwargs):
        raise AssertionError("the guard's index built FastAPI's OpenAPI document")
    monkeypatch.setattr(fastapi.openapi.utils, "get_openapi", no_document)
    monkeypatch.setattr(fastapi.applications, "get_openapi", no_document)
    monkeypatch.setattr(app, "openapi", no_document)
    ops = openapi.operations(app)
    assert app.openapi_schema is None              # built on its first request only
    assert ops.methods("/api/v1/eval") == ["GET", "POST"]
    assert "theta_i_deg" in {p["name"] for p in ops.operation("/api/v1/eval", "GET")["parameters"]}
    assert ops.operation("/api/v1/datasets", "POST")["x-body-limit"] == "max_upload_bytes"
