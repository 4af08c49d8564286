"""Writes only from the page's own origin (app/api/http/origin.py) and bodies only in
their operation's content types (app/api/http/content_types.py).

A foreign page can POST ``text/plain`` or ``multipart/form-data`` without a preflight
(Fetch standard §3.2.3), so these are the two a test sends from a foreign Origin; the
same upload from curl (no Origin) or from the server's own page still answers."""
from __future__ import annotations

import asyncio
import json
import warnings
from concurrent.futures import ThreadPoolExecutor

import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.api.http import origin
from app.config import Settings
from app.main import create_app
from tests.budget import settings_for_tests

#: TestClient's Host header is "testserver": the page's own origin is then this one
OWN = "http://testserver"
FOREIGN = "http://evil.example"
CSV = (b"theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n"
       b"30,0,30,180,1.5\n45,0,20,90,0.25\n60,0,40,180,0.75\n")
WRITES = [("/api/v1/datasets", "datasets"), ("/api/v1/lut/check?kind=kc_E", "lut")]


@pytest.fixture(scope="module")
def app():
    return create_app(settings_for_tests())


@pytest.fixture(scope="module")
def client(app):
    return TestClient(app)


@pytest.fixture(scope="module")
def lut_json(client):
    values = client.get("/api/v1/lut?kind=kc_E&size=8").json()["values"]
    return json.dumps({"values": values}).encode()


def _body(kind: str, lut_json: bytes) -> bytes:
    return CSV if kind == "datasets" else lut_json


def _asgi(app, method: str, path: str, headers: list, body: bytes):
    """(status, JSON body, bytes of the body the application pulled): a route that runs
    reads its body; one refused before any route pulls none of it."""
    pulled, sent = [0], []
    path, _, query = path.partition("?")

    async def receive():
        pulled[0] += len(body)
        return {"type": "http.request", "body": body, "more_body": False}

    async def send(message):
        sent.append(message)

    scope = {"type": "http", "method": method, "path": path, "raw_path": path.encode(),
             "query_string": query.encode(), "headers": [(k.encode(), v.encode()) for k, v in headers],
             "http_version": "1.1", "scheme": "http", "server": ("127.0.0.1", 80),
             "client": ("127.0.0.1", 1234), "root_path": ""}
    with ThreadPoolExecutor(max_workers=1) as pool:     # no running loop in this thread
        pool.submit(asyncio.run, app(scope, receive, send)).result()
    start = next(m for m in sent if m["type"] == "http.response.start")
    out = b"".join(m.get("body", b"") for m in sent if m["type"] == "http.response.body")
    return start["status"], dict(start["headers"]), out, pulled[0]


@pytest.mark.parametrize("path,kind", WRITES)
@pytest.mark.parametrize("content_type", ["text/plain", "multipart/form-data; boundary=x"])
def test_a_foreign_page_writes_nothing(app, lut_json, path, kind, content_type):
    headers = [("host", "brdf.example.org"), ("origin", FOREIGN), ("content-type", content_type)]
    status, sent_headers, out, pulled = _asgi(app, "POST", path, headers, _body(kind, lut_json))
    assert status == 403 and pulled == 0, out
    msg = json.loads(out)["detail"][0]
    assert FOREIGN in msg["msg"] and origin.ALLOWED_ORIGINS_ENV in msg["msg"]
    assert msg["loc"] == ["header", "origin"]
    assert not any(k.startswith(b"access-control-") for k in sent_headers)


@pytest.mark.parametrize("method", ["PUT", "PATCH", "DELETE"])
def test_every_unsafe_method_from_a_foreign_page_is_refused(client, method):
    r = client.request(method, "/api/v1/datasets/00000000000000000000000000000000",
                       headers={"origin": FOREIGN})
    assert r.status_code == 403 and FOREIGN in r.text


def test_a_null_origin_is_foreign(client):
    # a sandboxed frame or a file: page sends "Origin: null"
    r = client.post("/api/v1/datasets", content=CSV, headers={"origin": "null", "content-type": "text/csv"})
    assert r.status_code == 403


def test_curl_and_the_own_page_still_upload(client, lut_json):
    for extra in ({}, {"origin": OWN}, {"origin": OWN + ":80"}):
        raw = client.post("/api/v1/datasets", content=CSV, headers={"content-type": "text/csv", **extra})
        assert raw.status_code == 201, (extra, raw.text)
        form = client.post("/api/v1/datasets", files={"file": ("a.csv", CSV, "text/csv")}, headers=extra)
        assert form.status_code == 201, (extra, form.text)
        bare = client.post("/api/v1/datasets", content=CSV, headers=extra)      # a notebook
        assert bare.status_code == 201, (extra, bare.text)
        lut = client.post("/api/v1/lut/check?kind=kc_E", content=lut_json,
                          headers={"content-type": "application/json", **extra})
        assert lut.status_code == 200, (extra, lut.text)


def test_the_own_origin_behind_a_proxy_and_on_another_port():
    # Host as a proxy passes it, Origin as the browser saw the page (https, default port)
    ok = origin.foreign_origin
    from starlette.datastructures import Headers
    assert ok(Headers({"host": "brdf.example.org", "origin": "https://brdf.example.org"}), frozenset()) is None
    assert ok(Headers({"host": "brdf.example.org:443", "origin": "https://brdf.example.org"}), frozenset()) is None
    assert ok(Headers({"host": "127.0.0.1:8000", "origin": "http://127.0.0.1:8000"}), frozenset()) is None
    # another port of the same host is another origin (another service)
    assert ok(Headers({"host": "127.0.0.1:8000", "origin": "http://127.0.0.1:9000"}), frozenset())
    assert ok(Headers({"host": "brdf.example.org", "origin": "https://brdf.example.org.evil.example"}),
              frozenset())


def test_allowed_origins_may_write(monkeypatch):
    monkeypatch.setenv(origin.ALLOWED_ORIGINS_ENV, "https://tools.example.org, http://localhost:5173/")
    client = TestClient(create_app(Settings.from_env()))
    for allowed in ("https://tools.example.org", "http://localhost:5173"):
        r = client.post("/api/v1/datasets", content=CSV, headers={"origin": allowed, "content-type": "text/csv"})
        assert r.status_code == 201, r.text
    assert client.post("/api/v1/datasets", content=CSV,
                       headers={"origin": FOREIGN, "content-type": "text/csv"}).status_code == 403


def test_cors_headers_on_reads_only(client):
    read = client.get("/api/v1/ndf", headers={"origin": FOREIGN})
    assert read.status_code == 200 and read.headers["access-control-allow-origin"] == "*"
    write = client.post("/api/v1/datasets", content=CSV, headers={"origin": OWN, "content-type": "text/csv"})
    assert write.status_code == 201
    assert not [k for k in write.headers if k.lower().startswith("access-control-")]


@pytest.mark.parametrize("path,kind,accepted", [
    ("/api/v1/datasets", "datasets", "text/csv"),
    ("/api/v1/lut/check?kind=kc_E", "lut", "image/png"),
    ("/api/v1/eval", "eval", "application/json"),
])
@pytest.mark.parametrize("given", ["text/plain", "application/x-www-form-urlencoded"])
def test_a_body_of_another_type_is_415_naming_the_accepted(app, lut_json, path, kind, accepted, given):
    body = b'{"theta_i_deg": [30], "theta_o_deg": [30]}' if kind == "eval" else _body(kind, lut_json)
    status, _, out, pulled = _asgi(app, "POST", path, [("host", "testserver"), ("content-type", given)], body)
    assert status == 415 and pulled == 0, out
    msg = json.loads(out)["detail"][0]["msg"]
    assert accepted in msg and given in msg
