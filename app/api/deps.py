"""Typed dependencies of the routes: what a route needs from the application it is served
by (its settings, its data-set store, its operation index, its page files, the image
renderer), as ``Annotated[..., Depends(...)]`` aliases, so that no route reads
``request.app.state`` itself (FastAPI's "bigger applications" idiom).

:class:`Route` is the routers' route class: :class:`QueryModelRoute`'s one-pass query
reading, kept for an endpoint whose dependencies are these request-only ones (a figure's
GET takes ``Settings``; FastAPI's own handler read its ~46 query fields one by one, 1.9 ms
a request, BENCHMARKS.md §5).
"""
from __future__ import annotations

import inspect
import threading
from pathlib import Path
from typing import Annotated, Callable

from fastapi import Depends, Request
from fastapi.routing import APIRoute
from pydantic import BaseModel
from starlette.concurrency import run_in_threadpool
from starlette.responses import Response

from ..config import Settings, remote_scheme
from ..datasets.backends import open_store
from ..datasets.examples import WithExamples
from ..datasets.store import DatasetStore
from ..export.image import ImageRenderer, get_renderer
from .http.query_route import QueryModelRoute, read_query
from .openapi import Operations, operations

_STORE_LOCK = threading.Lock()
#: one client may hold this fraction of the data-set store (1/CLIENT_SHARE), so it cannot
#: evict everyone else's data sets by uploading
CLIENT_SHARE = 4


def get_settings(request: Request) -> Settings:
    """The settings the application was created with (app/main.py's create_app)."""
    return request.app.state.settings


def get_datasets(request: Request) -> WithExamples:
    """The application's data-set store, made on first use, kept across restarts (a
    quarter of BRDF_MAX_DATASETS_BYTES per client): at BRDF_DATA_URL, an fsspec URL such
    as s3://bucket/prefix shared by every host, or a directory shared by every worker of
    one host (default: the cache directory's ``datasets/``); in memory where that
    directory cannot be written (each worker then has its own). The server's example data
    sets (app/datasets/examples.py) answer their ids without an upload."""
    state = request.app.state
    with _STORE_LOCK:
        if not hasattr(state, "datasets"):
            s = state.settings
            location = s.data_url or s.cache_directory() / "datasets"
            try:
                store = open_store(location, s.max_datasets_bytes,
                                   client_bytes=s.max_datasets_bytes // CLIENT_SHARE)
            except OSError:
                if remote_scheme(str(location)):
                    raise                   # several hosts must not each keep their own
                store = DatasetStore(s.max_datasets_bytes)
            state.datasets = WithExamples(store)
        return state.datasets


def get_operations(request: Request) -> Operations:
    """The application's operation index (app/api/openapi.py), built once."""
    return operations(request.app)


def get_static_dir(request: Request) -> Path:
    """The directory the application serves at /static (wherever create_app mounted it)."""
    for route in request.app.router.routes:
        if getattr(route, "name", None) == "static":
            return Path(route.app.directory)
    raise LookupError("the application mounts no static directory")


SettingsDep = Annotated[Settings, Depends(get_settings)]
DatasetsDep = Annotated[WithExamples, Depends(get_datasets)]
OperationsDep = Annotated[Operations, Depends(get_operations)]
StaticDirDep = Annotated[Path, Depends(get_static_dir)]
RendererDep = Annotated[ImageRenderer, Depends(get_renderer)]

#: the dependencies above that are functions of the request alone (Route resolves them)
REQUEST_ONLY: frozenset[Callable] = frozenset({get_settings, get_datasets, get_operations,
                                               get_static_dir})


def _plan(route: APIRoute) -> tuple[type[BaseModel], str, str | None, list] | None:
    """(query model, its argument, the request's argument or None, [(argument,
    dependency)]) when the endpoint is a function (plain, or a coroutine that awaits the
    heavy pool) of one query model, the request and REQUEST_ONLY dependencies that returns
    a Response; None otherwise."""
    d = route.dependant
    returns = inspect.signature(route.endpoint).return_annotation
    deps = [(sub.name, sub.call) for sub in d.dependencies]
    if (not (isinstance(returns, type) and issubclass(returns, Response))
            or d.path_params or d.header_params or d.cookie_params or d.body_params
            or len(d.query_params) != 1 or any(call not in REQUEST_ONLY for _, call in deps)
            or any(sub.dependencies for sub in d.dependencies)
            or d.websocket_param_name or d.http_connection_param_name or d.response_param_name
            or d.background_tasks_param_name or d.security_scopes_param_name):
        return None
    field = d.query_params[0]
    model = field.field_info.annotation
    if not (isinstance(model, type) and issubclass(model, BaseModel)):
        return None
    return model, field.name, d.request_param_name, deps


class Route(QueryModelRoute):
    """A route of one query model read in one pass (QueryModelRoute), also when the
    endpoint takes the request-only dependencies of this module."""

    def get_route_handler(self) -> Callable:
        plan = _plan(self) if self.dependant.dependencies else None
        if plan is None:
            return super().get_route_handler()
        model, name, request_name, deps = plan
        endpoint = self.endpoint
        is_async = inspect.iscoroutinefunction(endpoint)

        async def app(request: Request) -> Response:
            args = {name: read_query(model, request.query_params)}
            args.update({arg: call(request) for arg, call in deps})
            if request_name:
                args[request_name] = request
            if is_async:           # its work is elsewhere (the heavy pool): awaited here
                return await endpoint(**args)
            return await run_in_threadpool(endpoint, **args)
        return app


def takes_the_fast_path(route: APIRoute) -> bool:
    """Whether the route reads its query model in one pass (a test holds every figure's):
    its handler is QueryModelRoute's or Route's, not FastAPI's."""
    return route.get_route_handler().__qualname__.endswith("Route.get_route_handler.<locals>.app")
