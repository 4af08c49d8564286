"""The HTTP layer around every route: limits on the request, headers on the response.

Outermost first (:func:`install`):

``SecurityHeaders``  nosniff, Content-Security-Policy, Referrer-Policy on every response,
                     errors and 304s included; an unhandled exception becomes a generic
                     500 here (no trace, no path), so it gets the headers too.
``CORSMiddleware``   cross-origin GET for embedding, nothing else (a POST preflight is
                     refused).
``HttpCache``        strong ETag (hash of the body as sent), If-None-Match → 304, and a
                     Cache-Control that says what a browser or CDN may reuse.
``GZipMiddleware``   bodies of 1000 bytes and more, when the client accepts gzip.
``RequestGuard``     the request itself: query string length (414), a scalar parameter
                     given twice (422), body size (413), a 405 listing every method of
                     the path; and the time budget of the request (BRDF_MAX_SECONDS).

All are plain ASGI callables: ``BaseHTTPMiddleware`` would copy every body through a
stream and run the route in another task.
"""
from __future__ import annotations

import base64
import hashlib
import json
import logging
import re
from collections import Counter
from pathlib import Path
from urllib.parse import parse_qsl

from fastapi import FastAPI
from fastapi.middleware.cors import CORSMiddleware
from starlette.concurrency import run_in_threadpool
from starlette.datastructures import Headers, MutableHeaders
from starlette.middleware.gzip import GZipMiddleware

from .. import warmup
from ..config import Settings
from ..integrate import budget

log = logging.getLogger("app")

#: bodies smaller than this are not worth a gzip header (and often grow)
GZIP_MINIMUM_SIZE = 1000
#: zlib level 6: within a few percent of level 9's size at a fraction of the CPU (the
#: 4.6 MB plotly.min.js: measured in docs/robustness.md)
GZIP_LEVEL = 6


def _json_error(status: int, loc: list, msg: str, kind: str) -> tuple[dict, bytes]:
    body = json.dumps({"detail": [{"loc": loc, "msg": msg, "type": kind}]}).encode()
    start = {"type": "http.response.start", "status": status,
             "headers": [(b"content-type", b"application/json"),
                         (b"content-length", str(len(body)).encode())]}
    return start, body


async def _send_error(send, status: int, loc: list, msg: str, kind: str) -> None:
    start, body = _json_error(status, loc, msg, kind)
    await send(start)
    await send({"type": "http.response.body", "body": body})


# ------------------------------------------------------------------------- security

def inline_script_hashes(static_dir: Path) -> list[str]:
    """CSP sources ('sha256-…') of the inline <script> blocks of the HTML files in
    ``static_dir``: the page's tiny boot script runs, any other inline script does not."""
    out = []
    for page in sorted(Path(static_dir).glob("*.html")):
        html = page.read_text(encoding="utf-8")
        for m in re.finditer(r"<script(?![^>]*\bsrc=)[^>]*>(.*?)</script>", html, re.S | re.I):
            digest = hashlib.sha256(m.group(1).encode("utf-8")).digest()
            out.append(f"'sha256-{base64.b64encode(digest).decode()}'")
    return sorted(set(out))


def content_security_policy(script_hashes: list[str]) -> str:
    """The page and the embeds load only same-origin scripts (app.js, plotly.min.js from
    /static/vendor/) and fetch only /api/v1. Plotly injects its stylesheet at run time and
    styles elements inline, hence 'unsafe-inline' for styles only (styles cannot run
    code); its modebar icons and image downloads use data: and blob: URLs. Any site may
    frame any page: nothing here acts on a user's behalf (no cookies, no sessions, no
    writes), so there is nothing to click-jack, and embedding is the point of /embed/*
    and ?embed=1."""
    return "; ".join([
        "default-src 'self'",
        "script-src " + " ".join(["'self'", *script_hashes]),
        "style-src 'self' 'unsafe-inline'",
        "img-src 'self' data: blob:",
        "font-src 'self' data:",
        "connect-src 'self'",
        "worker-src 'self' blob:",
        "object-src 'none'",
        "base-uri 'none'",
        "form-action 'self'",
        "frame-ancestors *",
    ])




class SecurityHeaders:
    def __init__(self, app, csp: str):
        self.app = app
        self.headers = [
            (b"x-content-type-options", b"nosniff"),
            (b"referrer-policy", b"no-referrer"),
            # JSON and images may be used by any site (the embeds); say so explicitly for
            # embedders that require it (Cross-Origin-Embedder-Policy).
            (b"cross-origin-resource-policy", b"cross-origin"),
        ]
        self.csp = csp.encode()

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        csp = self.csp
        started = False

        async def send_with_headers(message):
            nonlocal started
            if message["type"] == "http.response.start":
                started = True
                headers = MutableHeaders(scope=message)
                for name, value in (*self.headers, (b"content-security-policy", csp)):
                    if name.decode() not in headers:
                        headers.append(name.decode(), value.decode())
            await send(message)

        try:
            await self.app(scope, receive, send_with_headers)
        except Exception:
            # Never a stack trace or a file path in a response: the trace goes to the log.
            log.exception("unhandled error in %s %s", scope.get("method"), scope.get("path"))
            if started:
                raise
            start = {"type": "http.response.start", "status": 500,
                     "headers": [(b"content-type", b"application/json"),
                                 (b"cache-control", b"no-store")]}
            await send_with_headers(start)
            await send({"type": "http.response.body", "body": b'{"detail":"internal error"}'})


# ---------------------------------------------------------------------------- caching

def _etag_matches(if_none_match: str, etag: str) -> bool:
    """Weak comparison (RFC 9110 13.1.2): W/ prefixes are ignored; * matches any."""
    tags = {t.strip().removeprefix("W/") for t in if_none_match.split(",")}
    return "*" in tags or etag.removeprefix("W/") in tags


class HttpCache:
    """ETag and Cache-Control for GET; 304 when the client already has the body.

    Every response is a pure function of its URL and the app version (the service keeps
    no state), so its hash is a strong validator. It is taken of the body as sent — after
    gzip, which is deterministic here (zlib's gzip header has no time stamp) — so the
    identity and gzip representations have different tags, as RFC 9110 8.8.3 asks.
    Responses that carry a tag already (files) keep it, suffixed ``-gzip`` when
    compressed.

    Cache-Control: ``/api/*`` may be reused for ``BRDF_CACHE_MAX_AGE`` seconds (except
    health, never stored); pages and static files are revalidated each time
    (``no-cache``: a 304 costs a round trip, never a stale page after a deploy); errors
    are not stored.
    """

    def __init__(self, app, max_age: int):
        self.app = app
        self.api_cache = f"public, max-age={int(max_age)}".encode()

    def _policy(self, path: str) -> bytes:
        if path == "/api/v1/health":
            return b"no-store"
        if path.startswith("/api/"):
            return self.api_cache
        return b"no-cache"

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http" or scope["method"] not in ("GET", "HEAD"):
            await self.app(scope, receive, send)
            return
        if_none_match = Headers(scope=scope).get("if-none-match")
        policy = self._policy(scope["path"])
        start: dict | None = None
        chunks: list[bytes] = []
        mode = "pass"     # pass | buffer | drop (304 already sent)

        async def send_cached(message):
            nonlocal start, mode
            if message["type"] == "http.response.start":
                headers = MutableHeaders(scope=message)
                if message["status"] == 304:           # the file server's own revalidation
                    headers.setdefault("cache-control", policy.decode())
                    await send(message)
                    return
                if message["status"] != 200:
                    headers.setdefault("cache-control", "no-store")
                    await send(message)
                    return
                headers.setdefault("cache-control", policy.decode())
                etag = headers.get("etag")
                if etag is None:
                    start, mode = message, "buffer"
                    return
                if headers.get("content-encoding") == "gzip":
                    etag = etag[:-1] + '-gzip"' if etag.endswith('"') else etag + "-gzip"
                    headers["etag"] = etag
                if if_none_match and _etag_matches(if_none_match, etag):
                    mode = "drop"
                    await send(_not_modified(message))
                    await send({"type": "http.response.body", "body": b""})
                    return
                await send(message)
                return
            if message["type"] != "http.response.body" or mode == "pass":
                await send(message)
                return
            if mode == "drop":
                return
            chunks.append(message.get("body", b""))
            if message.get("more_body", False):
                return
            body = b"".join(chunks)
            etag = '"' + hashlib.blake2b(body, digest_size=16).hexdigest() + '"'
            headers = MutableHeaders(scope=start)
            headers["etag"] = etag
            if if_none_match and _etag_matches(if_none_match, etag):
                await send(_not_modified(start))
                await send({"type": "http.response.body", "body": b""})
                return
            await send(start)
            await send({"type": "http.response.body", "body": body})

        await self.app(scope, receive, send_cached)


def _not_modified(start: dict) -> dict:
    """A 304 with the headers RFC 9110 15.4.5 asks for (no body, no content headers)."""
    keep = {b"etag", b"cache-control", b"vary", b"content-location", b"date", b"expires"}
    return {"type": "http.response.start", "status": 304,
            "headers": [(k, v) for k, v in start.get("headers", []) if k.lower() in keep]}


# ------------------------------------------------------------------------------ limits

class RequestGuard:
    """Refuse what no route should see, and open the request's time budget.

    A scalar query parameter given twice (``alpha=0.1&alpha=0.2``) is ambiguous — the
    framework would silently take the last — so it is a 422 naming the parameter. Which
    parameters are lists (and may repeat: ``theta_i_deg=10&theta_i_deg=20``) is read from
    the OpenAPI document of the matched operation, so new endpoints are covered as they
    are added. For the same reason a query parameter sent to an operation that reads
    only a JSON body is refused rather than ignored.
    """

    def __init__(self, app, fastapi_app: FastAPI, settings: Settings):
        self.app = app
        self.fastapi_app = fastapi_app
        self.settings = settings
        self._paths: tuple[dict, list] | None = None

    def _operations(self, path: str) -> dict | None:
        """The OpenAPI path item of a request path: its operations by method."""
        if self._paths is None:
            self._paths = _path_index(self.fastapi_app.openapi())
        exact = self._paths[0].get(path)
        if exact is not None:
            return exact
        return next((item for regex, item in self._paths[1] if regex.fullmatch(path)), None)

    def _body_only(self, scope) -> bool:
        """An operation with a JSON body and no query parameters (POST /eval): a query
        parameter there would be ignored without a word."""
        item = self._operations(scope["path"])
        op = item.get(scope["method"].lower()) if item else None
        return bool(op and "requestBody" in op
                    and not any(p.get("in") == "query" for p in op.get("parameters", [])))

    def _list_params(self, scope) -> frozenset[str] | None:
        """Query parameters of the operation that are arrays (may repeat); None when the
        path is not an API operation."""
        item = self._operations(scope["path"])
        op = item.get(scope["method"].lower()) if item else None
        if op is None:
            return None
        out = set()
        for p in op.get("parameters", []):
            schema = p.get("schema", {})
            variants = [schema, *schema.get("anyOf", []), *schema.get("oneOf", [])]
            if p.get("in") == "query" and any(v.get("type") == "array" for v in variants):
                out.add(p["name"])
        return frozenset(out)

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        s = self.settings
        qs = scope.get("query_string", b"")
        if len(qs) > s.max_query_bytes:
            await _send_error(send, 414, ["query"],
                              f"the query string has {len(qs)} bytes; the limit is "
                              f"{s.max_query_bytes} (setting BRDF_MAX_QUERY_BYTES); send long "
                              "lists as a JSON body to POST /api/v1/eval", "query_too_long")
            return
        if qs:
            counts = Counter(k for k, _ in parse_qsl(qs.decode("latin-1"), keep_blank_values=True))
            if counts and self._body_only(scope):
                k = next(iter(counts))
                await _send_error(send, 422, ["query", k],
                                  f"{k}: this endpoint takes its parameters in the JSON body, "
                                  "not the query string", "extra_forbidden")
                return
            repeated = sorted(k for k, c in counts.items() if c > 1)
            if repeated:
                lists = self._list_params(scope)
                twice = [k for k in repeated if lists is not None and k not in lists]
                if twice:
                    k = twice[0]
                    await _send_error(send, 422, ["query", k],
                                      f"{k} given {counts[k]} times; give it once "
                                      "(only list parameters may repeat)", "duplicate_parameter")
                    return
        length = Headers(scope=scope).get("content-length")
        if length is not None and length.isdigit() and int(length) > s.max_body_bytes:
            await _send_error(send, 413, ["body"], self._body_message(int(length)), "body_too_large")
            return
        if length is None and scope["method"] in ("POST", "PUT", "PATCH"):
            # Chunked: read up to the limit before the route sees any of it (the route's
            # body reader would turn an error raised mid-stream into a vague 400).
            messages, received = [], 0
            while True:
                message = await receive()
                messages.append(message)
                received += len(message.get("body", b""))
                if received > s.max_body_bytes:
                    await _send_error(send, 413, ["body"], self._body_message(received),
                                      "body_too_large")
                    return
                if message["type"] != "http.request" or not message.get("more_body", False):
                    break
            replay = iter(messages)

            async def receive_buffered():
                return next(replay, None) or await receive()

            receive = receive_buffered

        started = False
        request_budget: budget.Budget | None = None

        async def send_fixed(message):
            nonlocal started
            if message["type"] == "http.response.start":
                started = True
                if request_budget is not None and request_budget.notes:
                    # cut short: say so, and let no cache keep this answer
                    headers = MutableHeaders(scope=message)
                    headers["x-time-budget"] = (
                        f"cut; {len(request_budget.notes)} computation(s) stopped early to "
                        f"end within BRDF_MAX_SECONDS={s.max_seconds:g}")
                    headers["cache-control"] = "no-store"
                item = self._operations(scope["path"]) if message["status"] == 405 else None
                if item:
                    # Starlette lists the methods of the first route of the path only
                    # (GET for /api/v1/eval, which also takes POST).
                    methods = sorted(m.upper() for m in item if m in _HTTP_METHODS)
                    MutableHeaders(scope=message)["allow"] = ", ".join(methods)
            await send(message)

        if not warmup.done():
            # an app served without its lifespan: compile before the budget's clock starts
            await run_in_threadpool(warmup.warm_up)
        with budget.limit(s.max_seconds) as request_budget:
            await self.app(scope, receive, send_fixed)

    def _body_message(self, size: int) -> str:
        return (f"the request body has {size} bytes or more; the limit is "
                f"{self.settings.max_body_bytes} (setting BRDF_MAX_BODY_BYTES)")


_HTTP_METHODS = {"get", "put", "post", "delete", "options", "head", "patch", "trace"}


def _path_index(openapi: dict) -> tuple[dict, list]:
    """OpenAPI path items by literal path, and (regex, item) for templated paths."""
    exact, templated = {}, []
    for path, item in openapi.get("paths", {}).items():
        if "{" in path:
            pattern = re.sub(r"\\\{[^/]+?\\\}", "[^/]+", re.escape(path))
            templated.append((re.compile(pattern), item))
        else:
            exact[path] = item
    return exact, templated


#: responses any operation may give, besides its own: from :class:`RequestGuard` (413,
#: 414, 422 for a repeated parameter) and from validation (422)
_GUARD_RESPONSES = {
    "413": "Request body above BRDF_MAX_BODY_BYTES, or a batch above its limit",
    "414": "Query string above BRDF_MAX_QUERY_BYTES",
    "422": "A parameter out of its range, unknown, repeated, or above a size limit; "
           "the message names it and what it allows",
}


def document_errors(app: FastAPI) -> None:
    """Add the error responses every operation can give to the OpenAPI document, so that
    a client (and a schema-driven test) knows every status it may see: 413, 414 and 422
    everywhere, 400 (body that is not JSON) where there is a body, 404 where the path
    has a parameter (an unknown name). All have the body
    ``{"detail": [{"loc", "msg", "type"}]}`` (FastAPI's own 400 has a string detail)."""
    build = app.openapi

    def openapi() -> dict:
        if getattr(app.state, "errors_documented", False):
            return app.openapi_schema
        schema = build()
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
                if method not in _HTTP_METHODS:
                    continue
                responses = op.setdefault("responses", {})
                for code, text in _GUARD_RESPONSES.items():
                    responses.setdefault(code, {"description": text, **ref})
                if "requestBody" in op:
                    responses.setdefault("400", {"description": "Body that is not valid JSON", **ref})
                if any(p.get("in") == "path" for p in op.get("parameters", [])):
                    responses.setdefault("404", {"description": "No such resource", **ref})
        app.state.errors_documented = True
        return schema

    app.openapi = openapi


def install(app: FastAPI, settings: Settings, static_dir: Path) -> None:
    """Add the middlewares (the last added runs first, outermost) and document the
    responses they give."""
    document_errors(app)
    app.add_middleware(RequestGuard, fastapi_app=app, settings=settings)
    app.add_middleware(GZipMiddleware, minimum_size=GZIP_MINIMUM_SIZE, compresslevel=GZIP_LEVEL)
    app.add_middleware(HttpCache, max_age=settings.cache_max_age)
    app.add_middleware(CORSMiddleware, allow_origins=list(settings.cors_origins),
                       allow_methods=["GET"], allow_headers=[])
    app.add_middleware(SecurityHeaders,
                       csp=content_security_policy(inline_script_hashes(static_dir)))
