"""The HTTP layer (app/api/http/): security headers, CORS, gzip, ETag and
Cache-Control, static files confined to static/, and no internals in any response."""
from __future__ import annotations

import base64
import gzip
import hashlib
import json
import re
import warnings
from pathlib import Path

import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app import quantities
from app.config import Settings
from tests.budget import settings_for_tests
from app.main import STATIC_DIR, create_app

ROOT = Path(__file__).resolve().parents[2]


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(settings_for_tests()))


# ---------------------------------------------------------------------------- headers

def _every_kind_of_response(client):
    """One response of each kind the app gives: data, figure, page, static file, the
    plotly bundle, 304, 404, 405, 414, 422, CORS preflight (allowed and refused)."""
    r = client.get("/api/v1/ndf")
    return {
        "data": r,
        "figure": client.get("/api/v1/figures/g1"),
        "page": client.get("/"),
        "static": client.get("/static/js/app/main.js"),
        "plotly": client.get("/static/vendor/plotly.min.js"),
        "304": client.get("/api/v1/ndf", headers={"if-none-match": r.headers["etag"]}),
        "404": client.get("/no/such/page"),
        "405": client.delete("/api/v1/ndf"),
        "414": client.get("/api/v1/ndf?alpha=0.3" + "&" * 20000),
        "422": client.get("/api/v1/ndf?alpha=7"),
        "preflight": client.options("/api/v1/ndf", headers={
            "origin": "https://example.org", "access-control-request-method": "GET"}),
        "preflight-refused": client.options("/api/v1/eval", headers={
            "origin": "https://example.org", "access-control-request-method": "POST"}),
    }


def test_security_headers_on_every_response(client):
    for kind, r in _every_kind_of_response(client).items():
        h = r.headers
        assert h.get("x-content-type-options") == "nosniff", kind
        assert h.get("referrer-policy") == "no-referrer", kind
        csp = h.get("content-security-policy", "")
        assert "default-src 'self'" in csp, (kind, csp)
        # no frame-ancestors: any page may frame, a file: page included (test_embed_framing)
        assert "frame-ancestors" not in csp and "x-frame-options" not in h, (kind, csp)
        assert "unsafe-eval" not in csp, (kind, csp)
        script_src = re.search(r"script-src ([^;]*)", csp).group(1)
        assert "unsafe-inline" not in script_src and "*" not in script_src.split(), (kind, csp)


def test_csp_allows_exactly_the_inline_scripts_of_the_pages(client):
    """The page's inline boot script runs (its hash is in script-src), nothing else
    inline does: the hashes in the policy are those of static/*.html's inline scripts."""
    expected = set()
    for page in STATIC_DIR.glob("*.html"):
        for body in re.findall(r"<script>(.*?)</script>", page.read_text(encoding="utf-8"), re.S):
            expected.add("'sha256-" + base64.b64encode(hashlib.sha256(body.encode()).digest()).decode() + "'")
    csp = client.get("/").headers["content-security-policy"]
    script_src = re.search(r"script-src ([^;]*)", csp).group(1).split()
    assert set(s for s in script_src if s.startswith("'sha256-")) == expected


def test_docs_page_is_served_offline_under_the_site_policy(client):
    """/docs loads Swagger UI from this server (the fastapi-offline package's files), with
    no inline script, under the same policy as the page; ReDoc (CDN only) is off."""
    r = client.get("/docs")
    assert r.status_code == 200
    assert r.headers["content-security-policy"] == client.get("/").headers["content-security-policy"]
    sources = re.findall(r'(?:src|href)="([^"]+)"', r.text)
    assert sources and all(s.startswith("/") and not s.startswith("//") for s in sources), sources
    assert "<script>" not in r.text
    for s in sources:
        assert client.get(s).status_code == 200, s
    assert client.get("/redoc").status_code == 404


# ------------------------------------------------------------------------------- CORS

def test_cors_allows_cross_origin_get(client):
    r = client.get("/api/v1/ndf", headers={"origin": "https://blog.example.org"})
    assert r.status_code == 200 and r.headers["access-control-allow-origin"] == "*"
    r = client.options("/api/v1/figures/lobe", headers={
        "origin": "https://blog.example.org", "access-control-request-method": "GET"})
    assert r.status_code == 200 and "GET" in r.headers["access-control-allow-methods"]


@pytest.mark.parametrize("method", ["POST", "PUT", "DELETE", "PATCH"])
def test_cors_refuses_every_other_method(client, method):
    r = client.options("/api/v1/eval", headers={
        "origin": "https://blog.example.org", "access-control-request-method": method})
    assert r.status_code == 400
    assert method not in r.headers.get("access-control-allow-methods", "")


def test_cors_refuses_custom_request_headers(client):
    r = client.options("/api/v1/ndf", headers={
        "origin": "https://blog.example.org", "access-control-request-method": "GET",
        "access-control-request-headers": "x-api-key"})
    assert r.status_code == 400


def test_allow_header_lists_every_method_of_the_path(client):
    r = client.delete("/api/v1/eval")
    assert r.status_code == 405
    assert set(r.headers["allow"].replace(" ", "").split(",")) == {"GET", "POST"}


# ------------------------------------------------------------------------------- gzip

def test_large_responses_are_gzipped_small_ones_not(client):
    big = client.get("/api/v1/lobe3d", headers={"accept-encoding": "gzip"})
    assert big.headers["content-encoding"] == "gzip"
    assert "accept-encoding" in big.headers["vary"].lower()
    small = client.get("/api/v1/health", headers={"accept-encoding": "gzip"})
    assert "content-encoding" not in small.headers
    plain = client.get("/api/v1/lobe3d", headers={"accept-encoding": "identity"})
    assert "content-encoding" not in plain.headers
    assert big.json() == plain.json()          # httpx decodes the gzip one


@pytest.mark.parametrize("url, fast", [("/api/v1/lobe3d", True), ("/static/vendor/plotly.min.js", False)])
def test_answers_made_per_request_are_compressed_fast_files_small(client, url, fast):
    """The gzip header's XFL byte says how zlib compressed (RFC 1952): 4 for its fastest
    level (1), 0 for the levels between (6, the files'), 2 for its smallest (9)."""
    with client.stream("GET", url, headers={"accept-encoding": "gzip"}) as r:
        raw = b"".join(r.iter_raw())
    assert raw[:2] == b"\x1f\x8b" and raw[8] == (4 if fast else 0)


def test_gzip_body_is_a_valid_gzip_stream(client):
    with client.stream("GET", "/api/v1/lobe3d", headers={"accept-encoding": "gzip"}) as r:
        raw = b"".join(r.iter_raw())
    assert json.loads(gzip.decompress(raw)) == client.get("/api/v1/lobe3d").json()


# ------------------------------------------------------------------- ETag, Cache-Control

@pytest.mark.parametrize("url", ["/api/v1/ndf?alpha=0.2", "/api/v1/figures/lobe", "/api/v1/models",
                                 "/", "/static/js/app/main.js", "/static/vendor/plotly.min.js"])
@pytest.mark.parametrize("encoding", ["gzip", "identity"])
def test_etag_and_304(client, url, encoding):
    first = client.get(url, headers={"accept-encoding": encoding})
    etag = first.headers["etag"]
    assert re.fullmatch(r'"[^"]+"', etag), etag            # strong
    again = client.get(url, headers={"accept-encoding": encoding})
    assert again.headers["etag"] == etag and again.content == first.content
    r = client.get(url, headers={"accept-encoding": encoding, "if-none-match": etag})
    assert r.status_code == 304 and r.content == b""
    assert r.headers["etag"] == etag and r.headers["cache-control"] == first.headers["cache-control"]
    for other in ('"something-else"', 'W/"x", "y"'):
        assert client.get(url, headers={"accept-encoding": encoding,
                                        "if-none-match": other}).status_code == 200
    # weak comparison (RFC 9110 13.1.2), a list, and *
    for matching in (f"W/{etag}", f'"x", {etag}', "*"):
        assert client.get(url, headers={"accept-encoding": encoding,
                                        "if-none-match": matching}).status_code == 304


def test_etag_differs_between_encodings_and_bodies(client):
    """A strong tag names one representation: gzip and identity differ (RFC 9110 8.8.3),
    and so do two different figures."""
    gz = client.get("/api/v1/lobe3d", headers={"accept-encoding": "gzip"}).headers["etag"]
    plain = client.get("/api/v1/lobe3d", headers={"accept-encoding": "identity"}).headers["etag"]
    assert gz != plain
    other = client.get("/api/v1/lobe3d?alpha=0.2", headers={"accept-encoding": "gzip"}).headers["etag"]
    assert other != gz


def test_cache_control_policy(client):
    assert client.get("/api/v1/figures/ndf").headers["cache-control"] == "public, max-age=3600"
    assert client.get("/api/v1/health").headers["cache-control"] == "no-store"
    assert client.get("/api/v1/ndf?alpha=9").headers["cache-control"] == "no-store"
    assert client.get("/").headers["cache-control"] == "no-cache"
    assert client.get("/static/style.css").headers["cache-control"] == "no-cache"
    short = TestClient(create_app(Settings(cache_max_age=60)))
    assert short.get("/api/v1/ndf").headers["cache-control"] == "public, max-age=60"


# --------------------------------------------------------------------- path traversal

TRAVERSALS = [
    "/static/../app/main.py",
    "/static/../pyproject.toml",
    "/static/vendor/../../pyproject.toml",
    "/static/%2e%2e/app/main.py",
    "/static/%2E%2E/%2E%2E/etc/passwd",
    "/static/%252e%252e/app/main.py",
    "/static/..%2fapp%2fmain.py",
    "/static/..%5capp%5cmain.py",
    "/static/..\\app\\main.py",
    "/static//etc/passwd",
    "/static/%00../app/main.py",
    "/static/js/app/main.js%00.html",
    "/static/vendor/..%2f..%2fpyproject.toml",
    "/static/.%2e/.%2e/pyproject.toml",
]

SECRETS = [(ROOT / "app" / "main.py").read_bytes()[:200], (ROOT / "pyproject.toml").read_bytes()[:120],
           b"root:x:0:0"]


async def _raw_get(app, path: str):
    """Call the ASGI app with a raw path, as a server would pass it (the client
    libraries normalise '..' away before sending, so they cannot test this)."""
    from urllib.parse import unquote
    sent = []

    async def receive():
        return {"type": "http.request", "body": b"", "more_body": False}

    async def send(message):
        sent.append(message)

    scope = {"type": "http", "asgi": {"version": "3.0"}, "http_version": "1.1", "method": "GET",
             "scheme": "http", "path": unquote(path), "raw_path": path.encode(), "root_path": "",
             "query_string": b"", "headers": [(b"host", b"testserver")],
             "client": ("127.0.0.1", 1), "server": ("testserver", 80)}
    await app(scope, receive, send)
    status = next(m["status"] for m in sent if m["type"] == "http.response.start")
    body = b"".join(m.get("body", b"") for m in sent if m["type"] == "http.response.body")
    return status, body


@pytest.mark.parametrize("path", TRAVERSALS)
def test_static_files_only_from_static(path):
    import asyncio
    from concurrent.futures import ThreadPoolExecutor
    app = create_app(settings_for_tests())
    # In a thread of its own: the browser tests (pytest-playwright's sync API) leave an
    # event loop running in the main thread, where asyncio.run() refuses to start.
    with ThreadPoolExecutor(max_workers=1) as pool:
        status, body = pool.submit(asyncio.run, _raw_get(app, path)).result()
    assert status in (400, 404, 405), (path, status)
    for secret in SECRETS:
        assert secret not in body, path


def test_static_files_are_served(client):
    r = client.get("/static/js/app/main.js")
    assert r.status_code == 200 and r.headers["content-type"].startswith(("text/javascript",
                                                                         "application/javascript"))


# -------------------------------------------------------------------- internal errors

def test_internal_error_is_generic(client, monkeypatch, caplog):
    """A bug in a computation gives a 500 with a fixed body — no trace, no path, no
    message — with the security headers, and the trace goes to the log."""
    def boom(*args, **kwargs):
        raise RuntimeError(f"secret detail in {__file__}")

    monkeypatch.setattr(quantities, "ndf_curve", boom)
    with caplog.at_level("ERROR", logger="app"):
        r = client.get("/api/v1/ndf")
    assert r.status_code == 500
    assert r.json() == {"detail": "internal error"}
    assert b"secret" not in r.content and b".py" not in r.content and b"Traceback" not in r.content
    assert r.headers["x-content-type-options"] == "nosniff"
    assert r.headers["cache-control"] == "no-store"
    assert "secret detail" in caplog.text
