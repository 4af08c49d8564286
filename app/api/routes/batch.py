"""POST /api/v1/batch: several figure GETs in one round trip (the page's panels, one
request per slider move instead of one per panel).

Each entry of ``requests`` is the path and query of a ``GET /api/v1/figures/...``, and
its answer is that GET's: the same status, Cache-Control and JSON body (null for a body
that is not JSON), in order; a 503 also gives its Retry-After (``retry_after``, seconds),
which the page waits before it asks again. A figure's JSON GET (``/api/v1/figures/{view}``,
the page's every entry) is answered by the steps its route takes, without the HTTP
layers around it: the request guard's query checks, the route's query model, the view's
pipeline, the application's error handlers; one after another in one worker thread under
one time budget, as the parts of one request. As four GETs through the whole application
the page's four panels took 10–14 ms in process here, against 5–8 ms (BENCHMARKS.md §5).
Any other entry (an export, an unknown view) goes through the whole application as its
GET would.
"""
from __future__ import annotations

import asyncio
import json
from urllib.parse import urlsplit

from fastapi import APIRouter, Request, Response
from fastapi.exceptions import RequestValidationError
from pydantic import BaseModel, ConfigDict, Field
from starlette.concurrency import run_in_threadpool
from starlette.datastructures import QueryParams

from ...config import Settings
from ...errors import ParameterError
from ...export import build
from ...integrate import budget
from ..deps import SettingsDep
from ..http.caching import cache_control
from ..http.guard import json_error, query_refusal
from ..http.query_route import read_query
from .figures import FIGURE_GETS, figure_body

router = APIRouter(prefix="/api/v1")

#: what a batch may ask for: the figures' JSON, by GET
PREFIX = "/api/v1/figures/"
MAX_REQUESTS = 16

#: an answer: (status, Cache-Control, JSON body or None, Retry-After or None)
Answer = tuple[int, str | None, bytes | None, str | None]


class BatchBody(BaseModel):
    """The GETs to answer, as paths with their queries (``/api/v1/figures/ndf?alpha=0.2``)."""
    model_config = ConfigDict(extra="forbid")
    requests: list[str] = Field(min_length=1, max_length=MAX_REQUESTS,
                                description=f"paths under {PREFIX} with their queries")


async def _through_the_app(request: Request, target: str) -> Answer:
    """``GET target`` through the whole application."""
    parts = urlsplit(target)
    outer = request.scope
    scope = {"type": "http", "asgi": outer.get("asgi", {"version": "3.0"}), "http_version": "1.1",
             "method": "GET", "scheme": outer.get("scheme", "http"), "path": parts.path,
             "raw_path": parts.path.encode("ascii"), "root_path": outer.get("root_path", ""),
             "query_string": parts.query.encode("ascii"),
             "headers": [(b"accept", b"application/json"), *[(k, v) for k, v in outer["headers"] if k == b"host"]],
             "client": outer.get("client"), "server": outer.get("server"),
             "state": dict(outer.get("state") or {}), "extensions": {}}
    status, headers, chunks = 500, [], []

    async def receive():
        return {"type": "http.request", "body": b"", "more_body": False}

    async def send(message):
        nonlocal status, headers
        if message["type"] == "http.response.start":
            status, headers = message["status"], message.get("headers", [])
        elif message["type"] == "http.response.body":
            chunks.append(message.get("body", b""))

    await request.app(scope, receive, send)
    head = {k.decode("latin-1").lower(): v.decode("latin-1") for k, v in headers}
    body = b"".join(chunks)
    is_json = head.get("content-type", "").startswith("application/json") and body
    return status, head.get("cache-control"), body if is_json else None, head.get("retry-after")


async def _handled(request: Request, exc: Exception) -> Answer:
    """The answer the application's handler for ``exc`` gives (as Starlette finds it: the
    nearest class in the exception's MRO)."""
    handlers = request.app.exception_handlers
    handler = next((handlers[c] for c in type(exc).__mro__ if c in handlers), None)
    if handler is None:            # the application handles Exception: not reached
        raise exc
    response = await handler(request, exc)
    return (response.status_code, response.headers.get("cache-control", "no-store"), response.body,
            response.headers.get("retry-after"))


def _compute(entries: list, settings: Settings) -> list:
    """Each (view, query)'s figure, one after another, under one time budget: (body, cut)
    or the exception it raised."""
    out = []
    with budget.limit(settings.max_seconds) as shared:
        for view, query in entries:
            cuts = len(shared.notes)
            try:
                out.append((figure_body(view, query, settings), len(shared.notes) > cuts))
            except Exception as exc:     # answered by the application's handler for it
                out.append(exc)
    return out


@router.post("/batch", tags=["figures"], response_class=Response,
             summary="Several figures in one request",
             openapi_extra={"requestBody": {"content": {"application/json": {"example": {
                 "requests": ["/api/v1/figures/ndf?alpha=0.2", "/api/v1/figures/g1?alpha=0.2"]}}}}},
             responses={200: {"content": {"application/json": {"example": {"responses": [
                 {"status": 200, "cache": "public, max-age=3600", "body": {"data": [], "layout": {}}},
                 {"status": 422, "cache": "no-store", "body": {"detail": [{"loc": ["query", "alpha"],
                                                                        "msg": "…", "type": "…"}]}},
                 {"status": 503, "cache": "no-store", "retry_after": 2, "body": {"detail": [
                     {"loc": ["query", "time budget"], "msg": "…: retry", "type": "busy"}]}}]}}}}})
async def batch(request: Request, settings: SettingsDep, body: BatchBody) -> Response:
    targets = [urlsplit(target) for target in body.requests]
    for k, (target, parts) in enumerate(zip(body.requests, targets)):
        if parts.scheme or parts.netloc or not parts.path.startswith(PREFIX) or parts.fragment:
            raise ParameterError(f"requests[{k}]", f"requests[{k}]: {target[:80]!r} is not a path under "
                                 f"{PREFIX} (a batch answers the figures' GETs only)", loc="body")
        if not target.isascii():
            raise ParameterError(f"requests[{k}]", f"requests[{k}]: {target[:80]!r} has characters "
                                 "a URL does not: percent-encode them", loc="body")
    app = request.app
    answers: list[Answer | None] = [None] * len(body.requests)
    direct, whole = [], []       # (k, view, query) for the figures' JSON; k for the rest
    for k, parts in enumerate(targets):
        view = FIGURE_GETS.get(parts.path)
        if view is None:
            whole.append(k)
            continue
        refusal = query_refusal(app, settings, parts.path, "GET", parts.query.encode("ascii"))
        if refusal is not None:
            answers[k] = (refusal.status, "no-store",
                          json_error(refusal.status, refusal.loc, refusal.message, refusal.kind)[1], None)
            continue
        try:
            direct.append((k, view, read_query(build.export_query(view), QueryParams(parts.query))))
        except RequestValidationError as exc:
            answers[k] = await _handled(request, exc)
    computed, answered = await asyncio.gather(
        run_in_threadpool(_compute, [(view, q) for _, view, q in direct], settings)
        if direct else asyncio.sleep(0, []),
        asyncio.gather(*(_through_the_app(request, body.requests[k]) for k in whole)))
    for (k, _, _), result in zip(direct, computed):
        if isinstance(result, Exception):
            answers[k] = await _handled(request, result)
        else:
            figure, cut = result
            # an answer cut short by the time budget is not to be kept (as the guard says)
            answers[k] = (200, "no-store" if cut else cache_control(PREFIX, settings.cache_max_age), figure, None)
    for k, answer in zip(whole, answered):
        answers[k] = answer
    out = [b'{"status":%d,"cache":%s,"body":%s%s}'
           % (status, json.dumps(cache).encode(), content if content is not None else b"null",
              b',"retry_after":%d' % int(retry) if status == 503 and retry and retry.isdigit() else b"")
           for status, cache, content, retry in answers]
    return Response(b'{"responses":[' + b",".join(out) + b"]}", media_type="application/json",
                    headers={"Cache-Control": "no-store"})
