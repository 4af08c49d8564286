"""Writes only from the page's own origin.

A browser sends a POST with ``Content-Type: text/plain`` or ``multipart/form-data`` to any
site without asking first (no CORS preflight: Fetch standard §3.2.3, "CORS-safelisted
request-header"), so any web page could upload through its visitors' browsers — and read
the answer while ``access-control-allow-origin: *`` was on every response. Browsers send
``Origin`` with every such request (RFC 6454 §7; Fetch §3.1, "origin header"), so:

* an unsafe method (POST, PUT, PATCH, DELETE) whose ``Origin`` is neither the server's own
  origin nor listed in ``BRDF_ALLOWED_ORIGINS`` is refused with 403 before any route runs;
* a request without ``Origin`` (curl, a notebook, a server) is unchanged: no browser is
  acting for a visitor there;
* the CORS headers (``access-control-*``) go only on GET, HEAD and OPTIONS answers: a
  foreign page may read figures and data (embedding), never the answer to a write.

"Own origin" is the request's ``Host`` header (what the browser connected to, which a
proxy passes on: docs/deploy.md) compared with the authority of ``Origin``, default ports
(80, 443) dropped from both. The scheme is not compared: behind a proxy that ends TLS the
server sees http where the browser saw https, and a page on another scheme of the same
host is the same operator's.
"""
from __future__ import annotations

import json
from urllib.parse import urlsplit

from starlette.datastructures import Headers, MutableHeaders

#: the methods that change something (RFC 9110 §9.2.1: not "safe")
UNSAFE_METHODS = frozenset({"POST", "PUT", "PATCH", "DELETE"})
#: the methods whose answers may carry CORS headers (OPTIONS: the preflight of a GET)
READ_METHODS = frozenset({"GET", "HEAD", "OPTIONS"})
#: the environment variable that lists the other origins allowed to write
ALLOWED_ORIGINS_ENV = "BRDF_ALLOWED_ORIGINS"
_DEFAULT_PORTS = {"http": "80", "https": "443"}


def allowed_origins(given) -> frozenset[str]:
    """The origins besides the server's own that may write: ``BRDF_ALLOWED_ORIGINS``,
    comma-separated (``https://tools.example.org,http://localhost:5173``), each normalised
    as :func:`origin_authority` compares them. Empty by default."""
    return frozenset(o.strip().rstrip("/").lower() for o in given if o.strip())


def _strip_default_port(authority: str, scheme: str) -> str:
    host, sep, port = authority.rpartition(":")
    return host if sep and port == _DEFAULT_PORTS.get(scheme) else authority


def origin_authority(origin: str) -> str | None:
    """``host[:port]`` of an Origin header, lower case, without the scheme's default
    port; None for ``null`` (a sandboxed frame, a file: page) or anything unparsable."""
    parts = urlsplit(origin.strip().lower())
    if parts.scheme not in _DEFAULT_PORTS or not parts.netloc:
        return None
    return _strip_default_port(parts.netloc, parts.scheme)


def host_authority(host: str) -> str:
    """The Host header as :func:`origin_authority` writes an authority (which default
    port to drop is not known from the Host header alone: either is dropped)."""
    host = host.strip().lower()
    for default in _DEFAULT_PORTS.values():
        if host.endswith(":" + default):
            return host[: -len(default) - 1]
    return host


def foreign_origin(headers: Headers, allowed: frozenset[str]) -> str | None:
    """The request's Origin when a browser sent it from a page that may not write here,
    else None (no Origin, the server's own, or listed in ``allowed``)."""
    origin = headers.get("origin")
    if origin is None:
        return None
    if origin.strip().rstrip("/").lower() in allowed:
        return None
    mine = host_authority(headers.get("host", ""))
    theirs = origin_authority(origin)
    return None if theirs is not None and theirs == mine else origin


def _refusal(origin: str, method: str) -> tuple[dict, bytes]:
    msg = (f"{method} from the page at {origin!r} is refused: only this server's own pages "
           f"may write here. To let that site write, list its origin in the setting "
           f"{ALLOWED_ORIGINS_ENV} (comma-separated). Requests without an Origin header "
           "(curl, scripts) are not affected.")
    body = json.dumps({"detail": [{"loc": ["header", "origin"], "msg": msg,
                                   "type": "foreign_origin"}]}).encode()
    start = {"type": "http.response.start", "status": 403,
             "headers": [(b"content-type", b"application/json"),
                         (b"content-length", str(len(body)).encode()),
                         (b"cache-control", b"no-store")]}
    return start, body


class SameOriginWrites:
    """Refuse unsafe methods from foreign pages (403); CORS headers on reads only.

    Sits outside the CORS middleware, so a refused write never reaches it and the CORS
    headers it adds to any other answer are taken off again.
    """

    def __init__(self, app, allowed: frozenset[str] | None = None):
        self.app = app
        self.allowed = allowed_origins(allowed or ())

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        method = scope["method"]
        if method in UNSAFE_METHODS:
            origin = foreign_origin(Headers(scope=scope), self.allowed)
            if origin is not None:
                start, body = _refusal(origin, method)
                await send(start)
                await send({"type": "http.response.body", "body": body})
                return
        if method in READ_METHODS:
            await self.app(scope, receive, send)
            return

        async def send_without_cors(message):
            if message["type"] == "http.response.start":
                headers = MutableHeaders(scope=message)
                for name in [k for k in headers.keys() if k.startswith("access-control-")]:
                    del headers[name]
            await send(message)

        await self.app(scope, receive, send_without_cors)
