"""HTTP caching for GET: a strong ETag (hash of the body as sent), If-None-Match → 304,
and a Cache-Control that says what a browser or CDN may reuse."""
from __future__ import annotations

import hashlib

from starlette.datastructures import Headers, MutableHeaders


def cache_control(path: str, max_age: int) -> str:
    """The Cache-Control of a 200 answer at ``path`` (see :class:`HttpCache`)."""
    if path == "/api/v1/health":
        return "no-store"
    if path.startswith("/api/"):
        return f"public, max-age={int(max_age)}"
    return "no-cache"


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
        self.max_age = max_age

    def _policy(self, path: str) -> bytes:
        return cache_control(path, self.max_age).encode()

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
