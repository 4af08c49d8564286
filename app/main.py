"""The application: routers, static files, error handlers. Nothing else."""
from __future__ import annotations

import asyncio
import logging
from contextlib import asynccontextmanager
from pathlib import Path

import fastapi_offline
from fastapi import APIRouter, FastAPI
from fastapi.routing import APIRoute
from fastapi.staticfiles import StaticFiles
from starlette.concurrency import run_in_threadpool

from . import __version__, allocator, kernels, work
from .api import errors, http, openapi
from .api.routes import (batch, code, conventions, datasets, environments, eval, exports, fallback, figures,
                         fit, lut, materials, meta, pages, principled, views)
from .config import Settings
from .model import make_spec
from .physics.ndf import NDFS
from .resources import static_dir
from .integrate import cost
from .integrate.tables import defaults as table_defaults, store as table_store

STATIC_DIR = static_dir()
PLOTLY_JS = pages.PLOTLY_JS
#: Swagger UI 5 (reads OpenAPI 3.1, which FastAPI writes), vendored by fastapi-offline
SWAGGER_UI_DIR = Path(fastapi_offline.__file__).resolve().parent / "static"


#: seconds after startup at which the heavy pool's workers are spawned: after the page's
#: first requests, which a clean start answers within ~3 s on two cores
WARM_POOL_AFTER_SECONDS = 1.0


@asynccontextmanager
async def lifespan(app: FastAPI):
    # The compiled loops load (or compile, on an empty numba cache) in a background
    # thread while requests take the numpy path; the log says when each is ready.
    # Index the operations, which the request guard reads to know each one's parameters:
    # from the routes, in milliseconds (FastAPI's OpenAPI document, which it was read
    # from, took 1-9 s here, and the port did not accept until then; the document is now
    # built on the first GET /openapi.json).
    allocator.return_large_frees_to_the_system()
    kernels.start(default_loops())
    await run_in_threadpool(openapi.operations, app)
    logging.getLogger("uvicorn.error").info(
        "compiled loops: %s", "loading in the background; numpy answers until each is ready"
        if kernels.ENABLED else "off (numba absent or BRDF_FAST=0): numpy answers")
    # The default models' E(μ, α) tables: read from the cache directory, or built there
    # by a background thread while the server answers (app/integrate/tables/store.py).
    settings = app.state.settings
    defaults = table_defaults.default_keys([make_spec(**v).brdf() for v in ({}, {"ndf": "beckmann"})])
    cache = await run_in_threadpool(
        table_store.start, settings.cache_directory(), defaults)
    logging.getLogger("uvicorn.error").info(
        "E(μ, α) tables: %s%s", cache or "in memory only",
        f", {len(table_store.building())} being built" if table_store.building() else "")
    # The heavy pool's workers spawned a moment after the port opens (each imports the
    # application in its own process), so that the first upload or export does not wait
    # for a fresh interpreter (~2-8 s here) inside its own time budget.
    asyncio.get_running_loop().call_later(WARM_POOL_AFTER_SECONDS, work.pool)
    yield
    work.close()      # the heavy pool's workers killed: shutdown never waits for a job


def default_loops() -> list[tuple]:
    """(model, part) of the loops the server loads first, in order: the page's default
    model, evaluated and integrated (its albedo panel); each NDF with the default
    options, evaluated (the menu's other choices); then the lobes of the tables
    (F = 1, the Smith masking and smith_numeric), integrated only: a table never
    evaluates f, and their f loops were about half of a cold start's compiling."""
    first = [(make_spec().brdf(), "f"), (make_spec().brdf(), "albedo")]
    per_ndf = [(make_spec(ndf=n).brdf(), "f") for n in NDFS]
    tables_ = [(make_spec(ndf=n, **extra).brdf(), "albedo") for n in NDFS
               for extra in ({"fresnel": "none"}, {"fresnel": "none", "masking": "smith_numeric"})]
    return first + per_ndf + tables_


#: /docs' groups, by task, in this order
TAGS = [
    {"name": "data", "description": "Numbers: the BRDF's terms at direction pairs (/eval), and "
                                    "each view's arrays (/albedo, /lobe, …)"},
    {"name": "figures", "description": "Plotly figures of every view, in every format; several "
                                       "models in one figure; several figures in one request"},
    {"name": "datasets", "description": "Measured data: upload, summary, the model against it, fits"},
    {"name": "code", "description": "For shader writers: the model as code, lookup tables, "
                                    "roughness conventions, measured materials"},
    {"name": "exports", "description": "The model as data files (MERL .binary, CSV of samples)"},
    {"name": "meta", "description": "What the page builds itself from: options, views, gallery"},
    {"name": "pages", "description": "Pages: embeds and the gallery"},
]


def with_head(router: APIRouter) -> APIRouter:
    """HEAD answered wherever GET is (RFC 9110 9.3.2: the GET's status and headers, no
    body; the server drops the body): a twin of each GET route taking HEAD, left out of
    the OpenAPI document (FastAPI's routes take only the methods they list)."""
    existing = {getattr(route, "name", None) for route in router.routes}
    twins = [type(route)(route.path, route.endpoint, methods=["HEAD"], include_in_schema=False,
                         name=f"{route.name}_head", response_class=route.response_class,
                         dependency_overrides_provider=route.dependency_overrides_provider)
             for route in router.routes if isinstance(route, APIRoute) and "GET" in route.methods
             and f"{route.name}_head" not in existing]
    # the routers are module-level: a second create_app (tests build many) must not add
    # a second twin of each route
    router.routes.extend(twins)
    return router


def create_app(settings: Settings | None = None) -> FastAPI:
    app = FastAPI(
        lifespan=lifespan,
        title="BRDF Lobe Explorer",
        version=__version__,
        description="Microfacet BRDFs — NDFs, Smith masking, G2, Fresnel, albedo — as numbers "
                    "and Plotly figures. Angles in degrees; α is the microfacet roughness.",
        # FastAPI's own /docs and /redoc load their scripts from a CDN: /docs is served
        # below from installed files instead, and ReDoc (no installable bundle) is off.
        docs_url=None, redoc_url=None, openapi_tags=TAGS,
    )
    app.state.settings = settings or Settings.from_env()
    cost.set_memory_limit(app.state.settings.max_request_bytes)
    errors.install(app)
    openapi.install(app, {"/api/v1/figures/{view}.{format}": figures.format_operation()})
    http.install(app, app.state.settings, STATIC_DIR)
    # the most asked first: FastAPI tries the routes in order, ~10 µs each here (the
    # batch after the 147 routes before it took 2.5 ms of each slider move to find)
    for module in (batch, figures, eval, views, meta, pages, principled, code, conventions,
                   materials, lut, datasets, fit, exports, environments):
        app.include_router(with_head(module.router))
    # Swagger UI's script and stylesheet from the fastapi-offline package: /docs offline
    app.mount("/static/vendor/swagger-ui", StaticFiles(directory=SWAGGER_UI_DIR), name="swagger-ui")
    # last: any other /api/v1 path is a 405 or a 404 listing the views
    app.include_router(with_head(fallback.router))
    app.mount("/static", StaticFiles(directory=STATIC_DIR), name="static")
    return app


app = create_app()
