"""Commands generated from the REST API: every GET operation that is a function of its
query parameters alone (no path parameter, body or server state) is a command named by
its path — ``/api/v1/code`` → ``code``, ``/api/v1/conventions/check`` →
``conventions-check`` — with the same parameters as options and the same validation,
and it calls the operation's own function: what the API answers is what the command
prints (or writes with ``-o``). A capability added to the API is a command with no
change here; the figures (views) are ``export``'s kinds instead."""
from __future__ import annotations

import argparse
import asyncio
import concurrent.futures
import inspect
from dataclasses import dataclass
from functools import lru_cache
from typing import Callable

from pydantic import BaseModel, create_model

from .options import UsageError, add_fields, add_output, check_directory, given, validate, write

PREFIX = "/api/v1/"


@dataclass(frozen=True)
class Operation:
    name: str                   # the command
    path: str                   # the API's path
    summary: str
    endpoint: Callable
    models: dict                # argument name → (its query model, whether it is one scalar)


def _routes():
    from fastapi.routing import APIRoute

    from ..main import app
    try:
        from fastapi.routing import iter_route_contexts        # FastAPI ≥ 0.16x: included routers
        routes = iter_route_contexts(app.routes)
    except ImportError:                                         # pragma: no cover
        routes = app.routes
    for route in routes:
        if isinstance(getattr(route, "original_route", route), APIRoute) and route.include_in_schema:
            yield route


def _query_only(route) -> bool:
    d = route.dependant
    return ("GET" in route.methods and route.path_format.startswith(PREFIX)
            and not (d.path_params or d.header_params or d.cookie_params or d.body_params
                     or d.dependencies or d.request_param_name or d.http_connection_param_name
                     or d.websocket_param_name or d.response_param_name
                     or d.background_tasks_param_name or d.security_scopes_param_name))


def _models(route) -> dict:
    """Each argument of the endpoint as a model: a query model as it is, a scalar query
    parameter as a model of that one field (so both validate alike)."""
    out = {}
    for field in route.dependant.query_params:
        annotation = field.field_info.annotation
        if isinstance(annotation, type) and issubclass(annotation, BaseModel):
            out[field.name] = (annotation, False)
        else:
            out[field.name] = (create_model(field.name, **{field.name: (annotation, field.field_info)}), True)
    return out


@lru_cache(maxsize=1)
def operations() -> dict[str, Operation]:
    """The generated commands, by name (the app's routes are read once)."""
    found = {}
    for route in _routes():
        if _query_only(route):
            original = getattr(route, "original_route", route)
            name = route.path_format[len(PREFIX):].replace("/", "-").replace(".", "-").replace("_", "-")
            found[name] = Operation(name, route.path_format, original.summary or "", route.endpoint,
                                    _models(route))
    return found


def run(op: Operation, argv: list[str]) -> int:
    """Parse ``argv`` with the operation's parameters, call it, write its answer."""
    from ..errors import Busy, ParameterError
    parser = argparse.ArgumentParser(prog=f"brdf-explorer {op.name}", allow_abbrev=False,
                                     description=f"{op.summary} (the API's GET {op.path}).")
    add_output(parser, required=False)
    for model, _ in op.models.values():
        add_fields(parser, model)
    args = parser.parse_args(argv)
    kwargs = {}
    for arg, (model, scalar) in op.models.items():
        q = validate(model, given(args, model))
        kwargs[arg] = getattr(q, arg) if scalar else q
    if args.output is not None:
        check_directory(args.output, args.mkdir)
    try:
        answer = op.endpoint(**kwargs)
        if inspect.isawaitable(answer):
            answer = _await(answer)
    except ParameterError as e:
        raise UsageError(f"{_name_of(e.param)}: {e.message}") from None
    except Busy as e:
        raise UsageError(f"busy: {e.message}; try again in {e.retry_after} s") from None
    write(_body(answer), args.output)
    return 0


def _await(coroutine):
    """The coroutine's result: on a new event loop, in a thread of its own when this
    thread already runs one (a notebook, or Playwright's sync API in the tests), where
    asyncio.run refuses."""
    try:
        asyncio.get_running_loop()
    except RuntimeError:
        return asyncio.run(coroutine)
    with concurrent.futures.ThreadPoolExecutor(max_workers=1) as thread:
        return thread.submit(asyncio.run, coroutine).result()


def _name_of(param: str) -> str:
    return "--" + param.replace("_", "-") if param.isidentifier() else param


def _body(answer) -> bytes:
    """The bytes the API would send: a Response's body, or JSON of a plain answer."""
    body = getattr(answer, "body", None)
    if isinstance(body, (bytes, bytearray)):
        return bytes(body)
    from ..export.jsonable import json_bytes
    return json_bytes(answer)
