"""POST /api/v1/batch answers a figure's JSON GET by the route's own steps, without the
HTTP layers (app/api/routes_batch.py): each entry must be exactly what the GET answers
through the whole application — status, Cache-Control and JSON body — for every view,
both spellings, every kind of refusal, an answer cut by the time budget, and the
entries that still go through the application (an export, an unknown view)."""
from __future__ import annotations

import json
import re
import warnings

import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.config import Settings
from app.main import create_app
from app.views import VIEWS
from tests.budget import settings_for_tests

F = "/api/v1/figures"
CHEAP = ("ndf", "g1", "lobe", "albedo", "g2", "fresnel", "checks", "advise")

TARGETS = [
    *(f"{F}/{name}?alpha=0.23" for name in CHEAP),
    f"{F}/ndf.json?alpha=0.31&ndf=beckmann",                 # the export spelling
    f"{F}/lobe?alpha=0.2&theta_i_deg=60&fresnel=conductor&material=gold",
    f"{F}/ndf?vary=alpha&values=0.1,0.3",                     # one curve per value
    f"{F}/albedo?alpha=0.2&method=auto&mu=0.1&mu=0.5",        # a list parameter repeated
    f"{F}/g1?alpha=7",                                        # out of range: 422
    f"{F}/g1?alpha=abc",                                      # not a number: 422
    f"{F}/g1?alpha=1_0",                                      # as no client writes it: 422
    f"{F}/g1?alpha=0.2&alpha=0.3",                            # a scalar twice: 422
    f"{F}/g1?nonsense=1",                                     # unknown parameter: 422
    f"{F}/ndf?ndf=nope",                                      # unknown choice: 422
    f"{F}/ndf?vary=alpha&values=0.1,9",                       # a value out of range: 422
    f"{F}/lobe?alpha=0.2&" + "theta_i_deg=1&" * 2000,         # query too long: 414
    f"{F}/ndf.csv?alpha=0.2",                                 # not JSON: status, no body
    f"{F}/nope?alpha=0.2",                                    # unknown view: 404
    f"{F}/ndf.txt",                                           # unknown format: 404
]


#: the time a computation took, as some titles say it ("46720 evaluations, 0.021 s"):
#: the one part of an answer that differs from one run to the next
SECONDS = re.compile(r"\b\d+(\.\d+)? s\b")


def _timeless(value):
    if isinstance(value, str):
        return SECONDS.sub("<seconds>", value)
    if isinstance(value, dict):
        return {k: _timeless(v) for k, v in value.items()}
    if isinstance(value, list):
        return [_timeless(v) for v in value]
    return value


def _as_get(client, target: str) -> dict:
    r = client.get(target)
    is_json = r.headers.get("content-type", "").startswith("application/json")
    return {"status": r.status_code, "cache": r.headers.get("cache-control"),
            "body": _timeless(r.json()) if is_json and r.content else None}


def _batch(client, targets: list[str]) -> list[dict]:
    r = client.post("/api/v1/batch", json={"requests": targets})
    assert r.status_code == 200, r.text
    assert r.headers["cache-control"] == "no-store"
    return _timeless(r.json()["responses"])


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(settings_for_tests()))


def test_every_entry_is_its_get_through_the_whole_application(client):
    kinds = set()
    for k in range(0, len(TARGETS), 8):                   # a batch holds up to 16
        chunk = TARGETS[k:k + 8]
        for target, answer in zip(chunk, _batch(client, chunk)):
            assert answer == _as_get(client, target), target
            kinds.add(answer["status"])
    assert kinds == {200, 404, 414, 422}


def test_every_view_with_its_defaults(client):
    names = [n for n in VIEWS if n not in CHEAP]
    for target, answer in zip(names, _batch(client, [f"{F}/{n}" for n in names])):
        assert answer == _as_get(client, f"{F}/{target}"), target


def test_an_answer_cut_by_the_time_budget_is_not_to_be_kept():
    """With a budget too small for the refinement the GET answers 200, marked cut and
    no-store; its batch entry says no-store too, and the body is the same cut answer."""
    client = TestClient(create_app(Settings(max_seconds=1e-3)))
    target = f"{F}/albedo?n=9&tol=1e-7&alpha=1e-4&alpha_y=1"
    get = client.get(target)
    assert get.status_code == 200 and "x-time-budget" in get.headers
    [answer] = _batch(client, [target])
    assert answer == _as_get(client, target)
    assert answer["cache"] == "no-store"


def test_an_entry_a_url_cannot_carry_is_refused_naming_it(client):
    r = client.post("/api/v1/batch", json={"requests": [f"{F}/ndf?alpha=0.2", f"{F}/ndf?ndf=☃"]})
    assert r.status_code == 422
    assert json.dumps(r.json()["detail"][0]["loc"]) == json.dumps(["body", "requests[1]"])


def test_a_busy_entry_says_when_to_ask_again(monkeypatch):
    """A 503 (busy) entry is its GET's status and body, plus the GET's Retry-After as
    ``retry_after``: the page waits that long before it asks again. No other entry has it."""
    from app.errors import Busy
    from app.export import build

    def busy(view, q, settings):
        raise Busy(f"the {view.name} table is being built: retry", retry_after=3, what="table")
    monkeypatch.setattr(build, "produce", busy)
    client = TestClient(create_app(settings_for_tests()))
    get = client.get(f"{F}/ndf?alpha=0.2")
    assert get.status_code == 503 and get.headers["retry-after"] == "3"
    answers = client.post("/api/v1/batch", json={"requests": [f"{F}/ndf?alpha=0.2", f"{F}/g1?alpha=7"]}).json()["responses"]
    assert answers[0] == {"status": 503, "cache": "no-store", "retry_after": 3, "body": get.json()}
    assert answers[1]["status"] == 422 and "retry_after" not in answers[1]
