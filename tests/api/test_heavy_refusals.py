"""A heavy view's request that can never be answered is refused (422, naming the
parameter) before it asks the heavy pool for a place: a busy pool must not turn it into a
503 to retry. The pool is stood in for by one that is always busy."""
from __future__ import annotations

import pytest

import app.work
from app.errors import Busy


@pytest.fixture
def busy_pool(monkeypatch):
    asked = []

    async def always_busy(fn, *args, **kwargs):
        asked.append(fn)
        raise Busy("every worker is busy", retry_after=3)
    monkeypatch.setattr(app.work, "run_heavy", always_busy)
    return asked


@pytest.mark.parametrize("path", ["/api/v1/samples", "/api/v1/figures/samples", "/api/v1/figures/samples.csv"])
def test_a_sampler_the_ndf_does_not_take_is_422_while_the_pool_is_busy(client, busy_pool, path):
    r = client.get(path, params={"ndf": "gtr", "sampler": "vndf", "n": 10})
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"][-1] == "sampler"
    assert busy_pool == []


def test_a_batch_answers_the_refused_heavy_entry_422_and_the_valid_one_503(client, busy_pool):
    r = client.post("/api/v1/batch", json={"requests": [
        "/api/v1/figures/samples?ndf=gtr&sampler=vndf&n=10", "/api/v1/figures/samples?ndf=ggx&sampler=vndf&n=10"]})
    assert r.status_code == 200, r.text
    refused, busy = r.json()["responses"]
    assert refused["status"] == 422 and refused["body"]["detail"][0]["loc"][-1] == "sampler"
    assert busy["status"] == 503 and busy["retry_after"] == 3


def test_the_valid_request_is_the_one_that_waits(client, busy_pool):
    r = client.get("/api/v1/samples", params={"ndf": "ggx", "sampler": "vndf", "n": 10})
    assert r.status_code == 503 and r.headers["Retry-After"] == "3"
    assert len(busy_pool) == 1
