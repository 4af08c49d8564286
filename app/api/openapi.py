"""The OpenAPI document: built once per app, on its first request, with the error
responses every operation can give; and an index of the operations by request path (what
the request guard reads to know which query parameters are lists or numbers, which
operations read a JSON body and which methods a path takes), built from the routes.

The index is the document's parameters and bodies reduced to what the guard reads: their
names, where they are, and the JSON types of their schemas, read off each route's
annotations. FastAPI's generator makes a pydantic schema of each of the ~3 700 flattened
query fields: 1-3 s at an idle start-up (the document is 2.7 MB), 7-9 s at load 9, and the
port did not accept until it was done. The index takes milliseconds, and a test holds it
equal to the document's for every operation (tests/api/test_route_index.py).
"""
from __future__ import annotations

import collections.abc
import decimal
import enum
import re
import threading
import types
import typing

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


def install(app: FastAPI, extra_paths: dict | None = None) -> None:
    """``app.openapi()`` builds the document on its first call (FastAPI's generator, the
    ``extra_paths`` that stand for routes left out of it, the error responses) and returns
    the same object afterwards."""
    generate = app.openapi
    # FastAPI's generator is not thread-safe: concurrent first requests of an app served
    # without its lifespan (which builds the document first) raised KeyError inside it
    lock = threading.Lock()

    def openapi() -> dict:
        with lock:
            if app.openapi_schema is None:
                document = generate()
                document["paths"].update(extra_paths or {})
                app.openapi_schema = _with_errors(document)
        return app.openapi_schema

    app.openapi = openapi


class Operations:
    """The document's operations by request path, indexed once: literal paths in a dict,
    templated ones (``/embed/{kind}``) as regular expressions."""

    def __init__(self, document: dict):
        self.document = document
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
        """The operation, a HEAD being its GET's."""
        item = self.item(path)
        return item.get("get" if method.upper() == "HEAD" else method.lower()) if item else None

    def methods(self, path: str) -> list[str]:
        item = self.item(path)
        return sorted(m.upper() for m in item if m in HTTP_METHODS) if item else []


def operations(app: FastAPI) -> Operations:
    """The app's operation index, built from its routes on first use and kept."""
    index = getattr(app.state, "operations", None)
    if index is None:
        index = app.state.operations = Operations(route_document(app))
    return index


# ------------------------------------------------------------- from the routes ------
_ARRAYS = (list, set, frozenset, collections.abc.Sequence, collections.abc.MutableSequence,
           collections.abc.Set, collections.abc.MutableSet, collections.abc.Iterable)
_SCALARS = {bool: "boolean", int: "integer", float: "number", str: "string",
            type(None): "null", bytes: "string"}
#: FastAPI's ValidationError schema, in the document of any app with a parameter or a
#: body: its ``loc`` (strings and integers) makes a numeric name, as it does there
_VALIDATION_ERROR = {"properties": {"loc": {"type": "array", "items": {
    "anyOf": [{"type": "string"}, {"type": "integer"}]}}}}


def _schema(annotation, models: dict) -> dict:
    """The JSON types of the schema pydantic writes for ``annotation`` (a model or an enum
    is a ``$ref`` there, so no type here; models met are collected into ``models``)."""
    origin, args = typing.get_origin(annotation), typing.get_args(annotation)
    if origin is typing.Annotated:
        return _schema(args[0], models)
    if origin is typing.Union or origin is types.UnionType:
        return {"anyOf": [_schema(a, models) for a in args]}
    if origin is typing.Literal:
        kinds = {_SCALARS.get(type(a)) for a in args}
        return {"type": kinds.pop()} if len(kinds) == 1 and None not in kinds else {}
    if origin is tuple:
        if len(args) == 2 and args[1] is Ellipsis:
            return {"type": "array", "items": _schema(args[0], models)}
        for a in args:
            _schema(a, models)
        return {"type": "array"}          # prefixItems: no "items"
    if origin in _ARRAYS or annotation in _ARRAYS:
        return {"type": "array", "items": _schema(args[0], models) if args else {}}
    if origin in (dict, collections.abc.Mapping) or annotation is dict:
        for a in args:
            _schema(a, models)
        return {"type": "object"}
    if isinstance(annotation, type):
        if issubclass(annotation, enum.Enum):
            return {}
        if annotation is decimal.Decimal:
            return {"anyOf": [{"type": "number"}, {"type": "string"}]}
        if hasattr(annotation, "model_fields"):
            if annotation not in models:
                models[annotation] = None
                models[annotation] = {"properties": {
                    (f.alias or name): _schema(f.annotation, models)
                    for name, f in annotation.model_fields.items()}}
            return {}
        if annotation in _SCALARS:
            return {"type": _SCALARS[annotation]}
    return {}


def _parameters(dependant, models: dict) -> list[dict]:
    """The operation's parameters as the document lists them: path, query, header,
    cookie, of the endpoint and its dependencies; a query model's fields one by one."""
    groups = {"path": [], "query": [], "header": [], "cookie": []}
    stack, seen = [dependant], set()
    while stack:
        d = stack.pop()
        if id(d) in seen:
            continue
        seen.add(id(d))
        for where in groups:
            groups[where].extend(getattr(d, f"{where}_params"))
        stack.extend(reversed(d.dependencies))
    out: dict[tuple[str, str], dict] = {}
    for where, fields in groups.items():
        for field in fields:
            info = field.field_info
            if not getattr(info, "include_in_schema", True):
                continue
            model = info.annotation
            if where != "path" and isinstance(model, type) and hasattr(model, "model_fields"):
                flat = [((f.alias or n), f.annotation) for n, f in model.model_fields.items()]
            else:
                flat = [(field.alias, info.annotation)]
            for name, annotation in flat:
                if where == "header" and getattr(info, "convert_underscores", True):
                    name = name.replace("_", "-")
                out[(where, name)] = {"name": name, "in": where,
                                      "schema": _schema(annotation, models)}
    return list(out.values())


def _merge(into: dict, extra: dict) -> None:
    for k, v in extra.items():
        if isinstance(v, dict) and isinstance(into.get(k), dict):
            _merge(into[k], v)
        else:
            into[k] = v


def _route_contexts(app: FastAPI):
    try:
        from fastapi.routing import iter_route_contexts
    except ImportError:   # a FastAPI that lists included routes in app.routes itself
        return app.routes
    return iter_route_contexts(app.routes)


def route_document(app: FastAPI) -> dict:
    """The OpenAPI document reduced to what the request guard reads (paths, methods,
    parameters' names, places and JSON types, request bodies' media types, the routes'
    ``openapi_extra``; the models' properties), from the routes, with no schema built."""
    from fastapi.routing import APIRoute
    paths: dict[str, dict] = {}
    models: dict = {}
    any_input = False
    for route in _route_contexts(app):
        original = getattr(route, "original_route", route)
        # the routes of the document, and the format twins it shows as one operation
        twin = (getattr(original, "openapi_extra", None) or {}).get("x-format-twin")
        if not isinstance(original, APIRoute) or not (route.include_in_schema or twin):
            continue
        params = _parameters(route.dependant, models)
        body = route.body_field
        any_input = any_input or bool(params) or body is not None
        item = paths.setdefault(route.path_format, {})
        for method in route.methods:
            op: dict = {"parameters": list(params)} if params else {}
            if body is not None and method in ("POST", "PUT", "PATCH", "DELETE"):
                _schema(body.field_info.annotation, models)
                op["requestBody"] = {"content": {body.field_info.media_type: {}}}
            if route.openapi_extra:
                _merge(op, route.openapi_extra)
            item[method.lower()] = op
    schemas = {m.__name__: s for m, s in models.items() if s is not None}
    if any_input:
        schemas["ValidationError"] = _VALIDATION_ERROR
    return {"paths": paths, "components": {"schemas": schemas}}
