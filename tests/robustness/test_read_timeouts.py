"""A request body that stops arriving is answered 408 after BRDF_BODY_IDLE_SECONDS of
silence (app/api/http/guard.py), whatever the route: uvicorn's --timeout-keep-alive
covers only the wait between requests. (Headers: docs/deploy.md, at the proxy.)"""
from __future__ import annotations

import asyncio
import json
import time
from concurrent.futures import ThreadPoolExecutor

import pytest

from app.config import Settings

from app.api.http import guard
from app.main import create_app
from tests.budget import settings_for_tests

IDLE = 0.3


@pytest.fixture(scope="module")
def app():
    import dataclasses
    return create_app(dataclasses.replace(settings_for_tests(), body_idle_seconds=IDLE))


def _stalled_post(app, path: str, headers: list, first: bytes):
    """POST whose body sends ``first`` and then nothing: (status, headers, body, seconds)."""
    sent, calls = [], [0]

    async def receive():
        calls[0] += 1
        if calls[0] == 1:
            return {"type": "http.request", "body": first, "more_body": True}
        await asyncio.sleep(3600)

    async def send(message):
        sent.append(message)

    scope = {"type": "http", "method": "POST", "path": path, "raw_path": path.encode(),
             "query_string": b"", "headers": headers, "http_version": "1.1", "scheme": "http",
             "server": ("127.0.0.1", 80), "client": ("127.0.0.1", 1234), "root_path": ""}
    t0 = time.perf_counter()
    with ThreadPoolExecutor(max_workers=1) as pool:
        pool.submit(asyncio.run, asyncio.wait_for(app(scope, receive, send), 30)).result()
    seconds = time.perf_counter() - t0
    start = next(m for m in sent if m["type"] == "http.response.start")
    body = b"".join(m.get("body", b"") for m in sent if m["type"] == "http.response.body")
    return start["status"], dict(start["headers"]), body, seconds


@pytest.mark.parametrize("path,headers", [
    ("/api/v1/datasets", [(b"content-type", b"text/csv"), (b"content-length", b"1000000")]),
    ("/api/v1/datasets", [(b"content-type", b"application/octet-stream"), (b"transfer-encoding", b"chunked")]),
    ("/api/v1/eval", [(b"content-type", b"application/json"), (b"content-length", b"5000")]),
])
def test_a_stalled_body_is_408_after_the_idle_time(app, path, headers):
    status, sent_headers, body, seconds = _stalled_post(app, path, headers, b"theta_i_deg,")
    assert status == 408, body
    assert IDLE <= seconds < IDLE + 5
    msg = json.loads(body)["detail"][0]
    assert msg["loc"] == ["body"] and guard.BODY_IDLE_ENV in msg["msg"]
    assert sent_headers.get(b"connection") == b"close"


def test_the_setting_is_checked_at_start(monkeypatch):
    monkeypatch.setenv(guard.BODY_IDLE_ENV, "soon")
    with pytest.raises(ValueError, match=guard.BODY_IDLE_ENV):
        Settings.from_env()
