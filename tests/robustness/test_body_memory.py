"""A request body the guard buffered is freed when the request ends, by reference
counting alone, and a route that reads past it reaches the server.

The guard's replaying receive used to call ``receive`` after that name had been rebound
to itself: a closure that referred to itself, holding every buffered message. Each full
``POST /api/v1/eval`` batch (~20 MB) then stayed alive until the cycle collector's oldest
generation ran: one uvicorn process went 296 → 461 MB over 9 batches and back to 309 MB
on a gc.collect() (bench/eval_memory.py; docs/robustness.md §3). The tests see that with
the collector off, deterministically, not by measuring memory.
"""
from __future__ import annotations

import asyncio
import gc
import json
import weakref
from concurrent.futures import ThreadPoolExecutor

import pytest

from app.api.http.guard import RequestGuard
from app.main import create_app
from tests.budget import settings_for_tests

BODY = json.dumps({"theta_i_deg": [10, 20], "theta_o_deg": [10, 30],
                   "phi_i_deg": [0], "phi_o_deg": [180]}).encode()
SCOPE = {"type": "http", "asgi": {"version": "3.0"}, "http_version": "1.1", "method": "POST",
         "scheme": "http", "path": "/api/v1/eval", "raw_path": b"/api/v1/eval", "root_path": "",
         "query_string": b"", "client": ("127.0.0.1", 1), "server": ("testserver", 80),
         # no Content-Length: chunked, read whole by the guard before the route
         "headers": [(b"host", b"testserver"), (b"content-type", b"application/json")]}


class Probe:
    """Rides in each message of the body: alive as long as a message is."""


@pytest.fixture(scope="module")
def settings():
    return settings_for_tests()


@pytest.fixture(scope="module")
def fastapi_app(settings):
    return create_app(settings)


def _serve(guard: RequestGuard, messages: list[dict]) -> list[dict]:
    """Run one request through ``guard`` (body in ``messages``, then a disconnect), in an
    event loop of its own thread (the browser tests leave one running in the main one)."""
    sent: list[dict] = []
    pending = list(messages) + [{"type": "http.disconnect"}]

    async def receive():
        return pending.pop(0)

    async def send(message):
        sent.append(message)

    with ThreadPoolExecutor(max_workers=1) as pool:
        pool.submit(asyncio.run, guard(dict(SCOPE), receive, send)).result()
    return sent


def _chunks() -> tuple[list[dict], list[weakref.ref]]:
    half = len(BODY) // 2
    probes = [Probe(), Probe()]
    messages = [{"type": "http.request", "body": BODY[:half], "more_body": True, "probe": probes[0]},
                {"type": "http.request", "body": BODY[half:], "more_body": False, "probe": probes[1]}]
    return messages, [weakref.ref(p) for p in probes]


async def _read_body(receive) -> bytes:
    body = b""
    while True:
        message = await receive()
        body += message.get("body", b"")
        if not message.get("more_body", False):
            return body


def test_a_buffered_body_is_freed_when_the_request_ends_without_the_cycle_collector(fastapi_app, settings):
    seen = []

    async def route(scope, receive, send):
        seen.append(await _read_body(receive))
        await send({"type": "http.response.start", "status": 204, "headers": []})
        await send({"type": "http.response.body", "body": b""})

    messages, probes = _chunks()
    was_enabled = gc.isenabled()
    gc.disable()
    try:
        sent = _serve(RequestGuard(route, fastapi_app=fastapi_app, settings=settings), messages)
        del messages
        assert seen == [BODY] and sent[0]["status"] == 204
        assert [p() for p in probes] == [None, None], "the buffered body outlived its request"
    finally:
        if was_enabled:
            gc.enable()


def test_a_route_reading_past_the_buffered_body_gets_the_servers_message(fastapi_app, settings):
    """After the replayed body, receive() is the server's (a disconnect here): it used to
    call itself until the recursion limit."""
    after = []

    async def route(scope, receive, send):
        await _read_body(receive)
        after.append(await receive())
        await send({"type": "http.response.start", "status": 204, "headers": []})
        await send({"type": "http.response.body", "body": b""})

    messages, _ = _chunks()
    _serve(RequestGuard(route, fastapi_app=fastapi_app, settings=settings), messages)
    assert after == [{"type": "http.disconnect"}]


def test_the_whole_application_still_answers_a_chunked_batch(fastapi_app):
    """The same request through every layer and the real route: the numbers come back."""
    messages, _ = _chunks()
    sent = _serve(fastapi_app, messages)
    start = next(m for m in sent if m["type"] == "http.response.start")
    body = b"".join(m.get("body", b"") for m in sent if m["type"] == "http.response.body")
    assert start["status"] == 200, body[:300]
    assert len(json.loads(body)["f"]) == 2
