"""The HTTP layer around every route, outermost first:

``security.SecurityHeaders``  nosniff, CSP, Referrer-Policy; an escaped exception → 500
``origin.SameOriginWrites``   writes only from the page's own origin; CORS headers on reads
``CORSMiddleware``            cross-origin GET for embedding, nothing else
``caching.HttpCache``         ETag, If-None-Match → 304, Cache-Control
``Compress``                  gzip for bodies of GZIP_MINIMUM_SIZE bytes and more
``guard.RequestGuard``        limits on the request itself (content types: content_types.py),
                              and its time budget

All are plain ASGI callables: ``BaseHTTPMiddleware`` would copy every body through a
stream and run the route in another task.
"""
from __future__ import annotations

from pathlib import Path
from typing import TYPE_CHECKING

# starlette's own classes (fastapi.middleware.cors re-exports this one), and no FastAPI
# or guard at import: the server's start-up stack (app/server.py) serves the page with
# these layers before the application is imported
from starlette.middleware.cors import CORSMiddleware
from starlette.middleware.gzip import GZipMiddleware

from ...config import Settings
from .caching import HttpCache
from .origin import SameOriginWrites
from .security import SecurityHeaders, content_security_policy, inline_script_hashes

if TYPE_CHECKING:
    from fastapi import FastAPI

#: bodies smaller than this are not worth a gzip header (and often grow)
GZIP_MINIMUM_SIZE = 1000
#: zlib level of the API's answers, compressed anew for each request: level 1. The 3-D
#: lobe's 141 KB of JSON took 8.8 ms at level 6 (of a 22 ms answer) and 2.4 ms at level 1,
#: for 48 KB instead of 43; a slider move's 17 KB batch 0.26 → 0.11 ms (BENCHMARKS.md §4).
API_GZIP_LEVEL = 1
#: zlib level of the page's files, sent many times and revalidated by their ETags: level
#: 6, within a few percent of level 9's size (the 4.8 MB plotly.min.js: 1.47 MB, against
#: 1.71 MB at level 1; docs/robustness.md)
FILE_GZIP_LEVEL = 6


class Compress:
    """gzip at API_GZIP_LEVEL for ``/api/`` and FILE_GZIP_LEVEL for the rest."""

    def __init__(self, app, minimum_size: int):
        self.api = GZipMiddleware(app, minimum_size=minimum_size, compresslevel=API_GZIP_LEVEL)
        self.files = GZipMiddleware(app, minimum_size=minimum_size, compresslevel=FILE_GZIP_LEVEL)

    async def __call__(self, scope, receive, send):
        api = scope["type"] == "http" and scope.get("path", "").startswith("/api/")
        await (self.api if api else self.files)(scope, receive, send)


def _outer_layers(settings: Settings, static_dir: Path) -> list:
    """(class, options) of the layers outside the request guard, innermost first."""
    return [
        (Compress, {"minimum_size": GZIP_MINIMUM_SIZE}),
        (HttpCache, {"max_age": settings.cache_max_age}),
        (CORSMiddleware, {"allow_origins": list(settings.cors_origins),
                          "allow_methods": ["GET"], "allow_headers": []}),
        (SameOriginWrites, {"allowed": settings.allowed_origins}),
        (SecurityHeaders, {"csp": content_security_policy(inline_script_hashes(static_dir))}),
    ]


def install(app: FastAPI, settings: Settings, static_dir: Path) -> None:
    """Add the middlewares (the last added runs first, outermost)."""
    from .guard import RequestGuard
    app.add_middleware(RequestGuard, fastapi_app=app, settings=settings)
    for cls, options in _outer_layers(settings, static_dir):
        app.add_middleware(cls, **options)


def wrap_outer(inner, settings: Settings, static_dir: Path):
    """``inner`` inside the same layers as the application's, but the request guard: the
    page's files answered while the application is still being imported (app/server.py)
    get the headers, ETags and compression the application gives them."""
    for cls, options in _outer_layers(settings, static_dir):
        inner = cls(inner, **options)
    return inner
