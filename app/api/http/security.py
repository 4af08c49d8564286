"""Security headers on every response (errors and 304s included): nosniff, the
Content-Security-Policy, Referrer-Policy. An unhandled exception that escapes the app
becomes a generic 500 here (no trace, no path), so it gets the headers too."""
from __future__ import annotations

import base64
import hashlib
import logging
import re
from pathlib import Path

from starlette.datastructures import MutableHeaders

log = logging.getLogger("app")


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
    """The page and the embeds load only same-origin scripts (static/js/**/*.js, plotly.min.js from
    /static/vendor/) and fetch only /api/v1. Plotly injects its stylesheet at run time and
    styles elements inline, hence 'unsafe-inline' for styles only (styles cannot run
    code); its modebar icons and image downloads use data: and blob: URLs.

    Any page may frame any page, a slide deck opened from disk included: nothing here
    acts on a user's behalf (no cookies, no sessions, no writes), so there is nothing to
    click-jack, and embedding is the point of /embed/* and ?embed=1. Hence no
    ``frame-ancestors`` directive at all: ``frame-ancestors *`` matches network schemes
    only, and a ``file:`` page could not frame an embed."""
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
