"""Where a request's time budget starts (app/api/http/guard.py): at its arrival, so that a
body the server reads counts against BRDF_MAX_SECONDS — a 30 MB upload took 0.6-0.8 s to
arrive over loopback at load 16, and its answer, cut at the budget counted from the body's
end, came 11.1-11.3 s after its first byte (the limit is 11) — but of a slow body only
its last BODY_COUNTED_SECONDS, or a slow link could never upload what a fast one can."""
from __future__ import annotations

import asyncio
import time

import pytest

from app.api.http.guard import BODY_COUNTED_SECONDS, RequestGuard
from app.integrate import budget
from app.main import create_app
from tests.budget import settings_for_tests

SETTINGS = settings_for_tests()
APP = create_app(SETTINGS)


def _clock_start(pieces: int, gap: float) -> tuple[float, float, float]:
    """(arrival, the body's end, the budget's start) of a CSV upload whose body comes in
    ``pieces`` messages ``gap`` seconds apart, seen by the route behind the guard."""
    seen = {}

    async def route(scope, receive, send):
        seen["start"] = budget.current().start
        await send({"type": "http.response.start", "status": 204, "headers": []})
        await send({"type": "http.response.body", "body": b""})

    guard = RequestGuard(route, fastapi_app=APP, settings=SETTINGS)
    left = [pieces]

    async def receive():
        await asyncio.sleep(gap)
        left[0] -= 1
        if left[0] == 0:
            seen["end"] = time.perf_counter()
        return {"type": "http.request", "body": b"theta_i_deg,f\n", "more_body": left[0] > 0}

    async def send(message):
        pass

    scope = {"type": "http", "method": "POST", "path": "/api/v1/datasets", "raw_path": b"/api/v1/datasets",
             "query_string": b"", "headers": [(b"content-type", b"text/csv")], "http_version": "1.1",
             "scheme": "http", "server": ("127.0.0.1", 80), "client": ("127.0.0.1", 1234), "root_path": ""}

    async def main():
        arrival = time.perf_counter()
        await guard(scope, receive, send)
        return arrival

    arrival = asyncio.run(main())
    return arrival, seen["end"], seen["start"]


@pytest.fixture(scope="module", autouse=True)
def warm():
    """The first request builds the guard's index of the OpenAPI operations (~1 s): once."""
    _clock_start(1, 0.0)


def test_a_body_that_arrives_within_the_allowance_counts_from_the_requests_arrival():
    arrival, end, start = _clock_start(4, 0.1)
    assert end - arrival >= 0.4
    assert arrival <= start <= arrival + 0.05, (start - arrival, end - arrival)


def test_a_slow_body_counts_only_its_last_allowance():
    arrival, end, start = _clock_start(4, (BODY_COUNTED_SECONDS + 0.6) / 4)
    assert end - arrival > BODY_COUNTED_SECONDS + 0.5
    assert abs((end - start) - BODY_COUNTED_SECONDS) <= 0.05, (start - arrival, end - arrival)
