"""Refusals decided from the request before any work: strict numbers, duplicate keys,
ambiguous framing, oversized lists, overlays that cannot be drawn, the parameter a model
error names, and error paths that never turn into a 500."""
from __future__ import annotations

import json
import time

import numpy as np
import pytest
from fastapi.testclient import TestClient

from app.api import errors as api_errors
from app.api.http import strict
from app.config import Settings
from app.main import create_app
from tests.budget import settings_for_tests

PAIR = {"theta_i_deg": [10], "theta_o_deg": [10], "phi_i_deg": [0], "phi_o_deg": [180]}
JSON = {"content-type": "application/json"}


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(settings_for_tests()), raise_server_exceptions=False)


def _detail(r):
    return r.json()["detail"][0]


@pytest.mark.parametrize("body, loc", [
    ('{"alpha": true, %s}', ["alpha"]),                  # read as α = 1 before
    ('{"theta_i_deg": [true], %s}', ["theta_i_deg", 0]),
    ('{"alpha": 0.2, "alpha": 0.5, %s}', ["alpha"]),    # the last one was kept
])
def test_json_bodies_are_strict(client, body, loc):
    rest = json.dumps({k: v for k, v in PAIR.items() if k not in body})[1:-1]
    r = client.post("/api/v1/eval", content=body % rest, headers=JSON)
    assert r.status_code == 422, r.text
    assert _detail(r)["loc"] == ["body", *loc]


def test_nan_is_not_json(client):
    r = client.post("/api/v1/eval", content='{"theta_i_deg": [NaN], "theta_o_deg": [1], '
                    '"phi_i_deg": [0], "phi_o_deg": [0]}', headers=JSON)
    assert r.status_code == 422 and "NaN" in _detail(r)["msg"]


def test_a_boolean_model_parameter_in_an_overlay_is_refused(client):
    r = client.post("/api/v1/figures/lobe", json={"models": [{"alpha": True}]})
    assert r.status_code == 422 and _detail(r)["loc"] == ["body", "models", 0, "alpha"]


@pytest.mark.parametrize("query, param", [("alpha=1_0", "alpha"), ("n=1_0", "n"),
                                          ("alpha=0_5", "alpha")])
def test_query_numbers_with_underscores_are_refused(client, query, param):
    """Python's float() reads 1_0 as 10: alpha=1_0 was answered as α = 10 → 422 for its
    range, and n=1_0 as n = 10."""
    r = client.get(f"/api/v1/lobe?{query}")
    assert r.status_code == 422 and _detail(r)["loc"] == ["query", param]
    assert "'_'" in _detail(r)["msg"]


def test_plain_numbers_still_pass(client):
    assert client.get("/api/v1/lobe?alpha=5e-1&n=7&theta_i_deg=+30.").status_code == 200
    assert client.post("/api/v1/eval", json={**PAIR, "alpha": 0.5}).status_code == 200


def test_content_length_with_chunked_is_refused(client):
    r = client.post("/api/v1/eval", content=json.dumps(PAIR),
                    headers={**JSON, "transfer-encoding": "chunked"})
    assert r.status_code == 400 and _detail(r)["loc"] == ["header", "transfer-encoding"]


def test_lists_above_the_batch_are_counted_off_the_event_loop_before_validation(monkeypatch):
    """A 24 MB body (under the body limit) was parsed and validated on the event loop for
    5 s before its length was judged: now it is parsed once in a worker thread and the
    413 names the list, the limit and the setting, before the route's validation."""
    import threading
    threads = []
    real = strict.parse_json
    monkeypatch.setattr(strict, "parse_json",
                        lambda *a: threads.append(threading.current_thread().name) or real(*a))
    app = create_app(settings_for_tests())
    c = TestClient(app)
    c.get("/api/v1/health")
    n = Settings().max_batch + 1
    rng = np.random.default_rng(0)
    body = json.dumps({k: rng.uniform(0, 90, n).round(13).tolist() for k in PAIR})
    assert len(body) > 15e6             # ~18 MB, under BRDF_MAX_BODY_BYTES
    r = c.post("/api/v1/eval", content=body, headers=JSON)
    assert r.status_code == 413
    d = _detail(r)
    assert d["loc"][0] == "body" and "BRDF_MAX_BATCH" in d["msg"] and str(n) in d["msg"]
    loop_thread = threading.main_thread().name
    assert threads and all(t != loop_thread for t in threads)


def test_eight_surfaces_are_refused_before_they_are_computed(client, monkeypatch):
    """POST /figures/lobe3d with eight 500×500 models computed them all (34 s) before
    answering that surfaces cannot be overlaid: now one 5×5 probe decides."""
    from app import quantities
    computed = []
    real_compute = quantities.lobe_grid
    monkeypatch.setattr(quantities, "lobe_grid",
                        lambda *a, **k: computed.append(a[-2] * a[-1]) or real_compute(*a, **k))
    models = [{"ndf": n, "alpha": 0.2} for n in ["ggx", "beckmann"] * 4]
    r = client.post("/api/v1/figures/lobe3d",
                    json={"models": models, "view": {"n_theta": 500, "n_phi": 500}})
    assert r.status_code == 422 and _detail(r)["loc"][-1] == "models"
    assert "cannot be overlaid" in _detail(r)["msg"]
    assert max(computed, default=0) <= 25


def test_samples_names_the_model_parameter_not_the_sampler(client):
    r = client.get("/api/v1/samples?ndf=gtr&alpha_y=0.5")
    assert r.status_code == 422 and _detail(r)["loc"][-1] == "alpha_y"
    r = client.get("/api/v1/samples?ndf=gtr&sampler=vndf")
    assert r.status_code == 422 and _detail(r)["loc"][-1] == "sampler"


@pytest.mark.parametrize("url, status", [
    ("/api/v1/lobe?alpha=7", 422),                                 # validation
    ("/api/v1/lobe?n=100000000", 422),                              # a limit
])
def test_an_error_inside_an_error_handler_keeps_its_status(monkeypatch, url, status):
    """The handler's own failure (here: its JSON encoder) is answered with the error's
    status and a generic body, never a 500."""
    monkeypatch.setattr(api_errors, "_respond", lambda *a, **k: 1 / 0)
    c = TestClient(create_app(settings_for_tests()), raise_server_exceptions=False)
    assert c.get(url).status_code == status


def test_out_of_memory_is_busy_not_a_500(monkeypatch):
    from app import quantities
    monkeypatch.setattr(quantities, "lobe_curve", lambda *a, **k: (_ for _ in ()).throw(MemoryError()))
    c = TestClient(create_app(settings_for_tests()), raise_server_exceptions=False)
    r = c.get("/api/v1/lobe?n=9")
    assert r.status_code == 503 and int(r.headers["retry-after"]) >= 1
