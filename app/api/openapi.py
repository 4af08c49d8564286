"""The OpenAPI document: built once per app, with the error responses every operation
can give, and an index of its operations by request path (what the request guard reads
to know which query parameters are lists and which methods a path takes)."""
from __future__ import annotations

import re
import threading

from fastapi import FastAPI

HTTP_METHODS = {"get", "put", "post", "delete", "options", "head", "patch", "trace"}

#: responses any operation may give, besides its own: from the request guard (413, 414,
#: 422 for a repeated parameter), from validation (422) and when busy (503)
GUARD_RESPONSES = {
    "413": "Request body above BRDF_MAX_BODY_BYTES, or a batch above its limit",
    "414": "Query string above BRDF_MAX_QUERY_BYTES",
    "422": "A parameter out of its range, unknown, repeated, or above a size limit; "
           "the message names it and what it allows",
    "503": "Valid, but the server cannot answer now (a table still building, a queue "
           "full): retry after the Retry-After header's seconds",
}


def _with_errors(schema: dict) -> dict:
    """Add the error responses every operation can give, so that a client (and a
    schema-driven test) knows every status it may see: 413, 414 and 422 everywhere, 400
    (body that is not JSON) where there is a body, 404 where the path has a parameter.
    All have the body ``{"detail": [{"loc", "msg", "type"}]}``."""
    schemas = schema.setdefault("components", {}).setdefault("schemas", {})
    item = ({"$ref": "#/components/schemas/ValidationError"} if "ValidationError" in schemas
            else {"type": "object", "required": ["loc", "msg", "type"]})
    schemas["Error"] = {
        "title": "Error", "type": "object", "required": ["detail"],
        "properties": {"detail": {"anyOf": [{"type": "string"},
                                            {"type": "array", "items": item}]}}}
    ref = {"content": {"application/json": {"schema": {"$ref": "#/components/schemas/Error"}}}}
    for path_item in schema.get("paths", {}).values():
        for method, op in path_item.items():
            if method not in HTTP_METHODS:
                continue
            responses = op.setdefault("responses", {})
            for code, text in GUARD_RESPONSES.items():
                responses.setdefault(code, {"description": text, **ref})
            if "requestBody" in op:
                responses.setdefault("400", {"description": "Body that is not valid JSON", **ref})
            if any(p.get("in") == "path" for p in op.get("parameters", [])):
                responses.setdefault("404", {"description": "No such resource", **ref})
    return schema


def install(app: FastAPI) -> None:
    """``app.openapi()`` builds the document on its first call (FastAPI's generator plus
    the error responses) and returns the same object afterwards."""
    generate = app.openapi
    # FastAPI's generator is not thread-safe: concurrent first requests of an app served
    # without its lifespan (which builds the document first) raised KeyError inside it
    lock = threading.Lock()

    def openapi() -> dict:
        with lock:
            if app.openapi_schema is None:
                app.openapi_schema = _with_errors(generate())
        return app.openapi_schema

    app.openapi = openapi


class Operations:
    """The document's operations by request path, indexed once: literal paths in a dict,
    templated ones (``/embed/{kind}``) as regular expressions."""

    def __init__(self, document: dict):
        self.exact, self.templated = {}, []
        for path, item in document.get("paths", {}).items():
            if "{" in path:
                pattern = re.sub(r"\\\{[^/]+?\\\}", "[^/]+", re.escape(path))
                self.templated.append((re.compile(pattern), item))
            else:
                self.exact[path] = item

    def item(self, path: str) -> dict | None:
        """The OpenAPI path item of a request path: its operations by method."""
        found = self.exact.get(path)
        if found is not None:
            return found
        return next((item for regex, item in self.templated if regex.fullmatch(path)), None)

    def operation(self, path: str, method: str) -> dict | None:
        item = self.item(path)
        return item.get(method.lower()) if item else None

    def methods(self, path: str) -> list[str]:
        item = self.item(path)
        return sorted(m.upper() for m in item if m in HTTP_METHODS) if item else []


def operations(app: FastAPI) -> Operations:
    """The app's operation index, built from its document on first use and kept."""
    index = getattr(app.state, "operations", None)
    if index is None:
        index = app.state.operations = Operations(app.openapi())
    return index
