"""POST /api/v1/batch: several figure GETs in one round trip (the page's panels, one
request per slider move instead of one per panel).

Each entry of ``requests`` is the path and query of a ``GET /api/v1/figures/...``; each
runs through the whole application, middlewares included, exactly as that GET would (the
same validation, errors, time budget and answer), all at once as separate GETs would run:
one after another, each waited its turn for a worker thread (on a loaded 2-core machine
the batch of four took as long as four GETs, or longer). What the batch saves is the
page's four fetches and the server's four HTTP exchanges. The answer lists, in order,
each one's status, its Cache-Control and its JSON body (null for a body that is not JSON).
"""
from __future__ import annotations

import asyncio
import json
from urllib.parse import urlsplit

from fastapi import APIRouter, Request, Response
from pydantic import BaseModel, ConfigDict, Field

from ..errors import ParameterError

router = APIRouter(prefix="/api/v1")

#: what a batch may ask for: the figures' JSON, by GET
PREFIX = "/api/v1/figures/"
MAX_REQUESTS = 16


class BatchBody(BaseModel):
    """The GETs to answer, as paths with their queries (``/api/v1/figures/ndf?alpha=0.2``)."""
    model_config = ConfigDict(extra="forbid")
    requests: list[str] = Field(min_length=1, max_length=MAX_REQUESTS,
                                description=f"paths under {PREFIX} with their queries")


async def _get(request: Request, target: str) -> tuple[int, str | None, bytes | None]:
    """``GET target`` through the whole application: (status, Cache-Control, JSON body)."""
    parts = urlsplit(target)
    outer = request.scope
    scope = {"type": "http", "asgi": outer.get("asgi", {"version": "3.0"}), "http_version": "1.1",
             "method": "GET", "scheme": outer.get("scheme", "http"), "path": parts.path,
             "raw_path": parts.path.encode("latin-1"), "root_path": outer.get("root_path", ""),
             "query_string": parts.query.encode("latin-1"),
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
    return status, head.get("cache-control"), body if is_json else None


@router.post("/batch", tags=["figures"], response_class=Response,
             summary="Several figures in one request",
             openapi_extra={"requestBody": {"content": {"application/json": {"example": {
                 "requests": ["/api/v1/figures/ndf?alpha=0.2", "/api/v1/figures/g1?alpha=0.2"]}}}}},
             responses={200: {"content": {"application/json": {"example": {"responses": [
                 {"status": 200, "cache": "public, max-age=3600", "body": {"data": [], "layout": {}}},
                 {"status": 422, "cache": None, "body": {"detail": [{"loc": ["query", "alpha"],
                                                                    "msg": "…", "type": "…"}]}}]}}}}})
async def batch(request: Request, body: BatchBody) -> Response:
    for k, target in enumerate(body.requests):
        parts = urlsplit(target)
        if parts.scheme or parts.netloc or not parts.path.startswith(PREFIX) or parts.fragment:
            raise ParameterError(f"requests[{k}]", f"requests[{k}]: {target[:80]!r} is not a path under "
                                 f"{PREFIX} (a batch answers the figures' GETs only)", loc="body")
    out = []
    for status, cache, content in await asyncio.gather(*(_get(request, t) for t in body.requests)):
        out.append(b'{"status":%d,"cache":%s,"body":%s}'
                   % (status, json.dumps(cache).encode(), content if content is not None else b"null"))
    return Response(b'{"responses":[' + b",".join(out) + b"]}", media_type="application/json",
                    headers={"Cache-Control": "no-store"})
