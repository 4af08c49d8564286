"""A faster request path for the GET routes that take one query model.

FastAPI reads a query model field by field, inspecting each field's type again on every
request: 1.9 ms for the ~46 fields of a figure's query, where the curve itself takes
0.4–1.2 ms (BENCHMARKS.md §5). :class:`QueryModelRoute` reads the query string in one
pass with each field's shape worked out once per model, and validates it in one
pydantic call, with FastAPI's rules: a sequence field takes every value of its key, any
other field the last; keys the model does not declare go to it as extras (which it
refuses); errors are located ("query", name). FastAPI still builds the OpenAPI document
from the endpoint's signature. Any other route takes FastAPI's own handler.
"""
from __future__ import annotations

import inspect
from functools import lru_cache
from typing import Any, Callable

from fastapi import Request
from fastapi.exceptions import RequestValidationError
from fastapi.routing import APIRoute
from pydantic import BaseModel, ValidationError
from starlette.concurrency import run_in_threadpool
from starlette.responses import Response

try:   # FastAPI's own test, so that a field is read exactly as FastAPI reads it
    from fastapi._compat import field_annotation_is_sequence
except ImportError:  # pragma: no cover - a FastAPI without it takes its own path
    field_annotation_is_sequence = None


@lru_cache(maxsize=None)
def _shape(model: type[BaseModel]) -> tuple[tuple[str, bool], ...]:
    """(query key, takes every value) for each field of ``model``."""
    return tuple((f.alias or name, bool(field_annotation_is_sequence(f.annotation)))
                 for name, f in model.model_fields.items())


def read_query(model: type[BaseModel], query) -> BaseModel:
    """``model`` from a request's query parameters (a Starlette multi-dict)."""
    values: dict[str, Any] = {}
    shape = _shape(model)
    for key, every in shape:
        if key not in query:
            continue
        v = query.getlist(key) if every else query[key]
        if not (every and len(v) == 0):
            values[key] = v
    known = {key for key, _ in shape}
    grouped: dict[str, list] = {}
    for key, v in query.multi_items():
        if key not in known:
            grouped.setdefault(key, []).append(v)
    for key, vs in grouped.items():
        values[key] = vs[0] if len(vs) == 1 else vs
    try:
        return model.model_validate(values)
    except ValidationError as exc:
        raise RequestValidationError([{**e, "loc": ("query", *e["loc"])}
                                      for e in exc.errors(include_url=False)]) from None


def _plan(route: APIRoute) -> tuple[type[BaseModel], str, str | None] | None:
    """(model, its argument's name, the request's argument's name or None) when the
    endpoint is a plain function of one query model (and the request) that returns a
    Response; None otherwise."""
    d = route.dependant
    returns = inspect.signature(route.endpoint).return_annotation
    if (field_annotation_is_sequence is None or inspect.iscoroutinefunction(route.endpoint)
            or not (isinstance(returns, type) and issubclass(returns, Response))
            or d.path_params or d.header_params or d.cookie_params or d.body_params
            or d.dependencies or len(d.query_params) != 1
            or d.websocket_param_name or d.http_connection_param_name or d.response_param_name
            or d.background_tasks_param_name or d.security_scopes_param_name):
        return None
    field = d.query_params[0]
    model = field.field_info.annotation
    if not (isinstance(model, type) and issubclass(model, BaseModel)):
        return None
    return model, field.name, d.request_param_name


class QueryModelRoute(APIRoute):
    """An APIRoute that reads a single query model itself (see the module's docstring)."""

    def get_route_handler(self) -> Callable:
        plan = _plan(self)
        if plan is None:
            return super().get_route_handler()
        model, name, request_name = plan
        endpoint = self.endpoint

        async def app(request: Request) -> Response:
            args = {name: read_query(model, request.query_params)}
            if request_name:
                args[request_name] = request
            return await run_in_threadpool(endpoint, **args)
        return app
