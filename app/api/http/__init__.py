"""The HTTP layer around every route, outermost first:

``security.SecurityHeaders``  nosniff, CSP, Referrer-Policy; an escaped exception → 500
``CORSMiddleware``            cross-origin GET for embedding, nothing else
``caching.HttpCache``         ETag, If-None-Match → 304, Cache-Control
``GZipMiddleware``            bodies of GZIP_MINIMUM_SIZE bytes and more
``guard.RequestGuard``        limits on the request itself, and its time budget

All are plain ASGI callables: ``BaseHTTPMiddleware`` would copy every body through a
stream and run the route in another task.
"""
from __future__ import annotations

from pathlib import Path

from fastapi import FastAPI
from fastapi.middleware.cors import CORSMiddleware
from starlette.middleware.gzip import GZipMiddleware

from ...config import Settings
from .caching import HttpCache
from .guard import RequestGuard
from .security import SecurityHeaders, content_security_policy, inline_script_hashes

#: bodies smaller than this are not worth a gzip header (and often grow)
GZIP_MINIMUM_SIZE = 1000
#: zlib level 6: within a few percent of level 9's size at a fraction of the CPU (the
#: 4.6 MB plotly.min.js: measured in docs/robustness.md)
GZIP_LEVEL = 6


def install(app: FastAPI, settings: Settings, static_dir: Path) -> None:
    """Add the middlewares (the last added runs first, outermost)."""
    app.add_middleware(RequestGuard, fastapi_app=app, settings=settings)
    app.add_middleware(GZipMiddleware, minimum_size=GZIP_MINIMUM_SIZE, compresslevel=GZIP_LEVEL)
    app.add_middleware(HttpCache, max_age=settings.cache_max_age)
    app.add_middleware(CORSMiddleware, allow_origins=list(settings.cors_origins),
                       allow_methods=["GET"], allow_headers=[])
    app.add_middleware(SecurityHeaders,
                       csp=content_security_policy(inline_script_hashes(static_dir)))
