"""Bad input, by hand, for every endpoint the view registry generates (so new views are
covered as they land): NaN, ±Infinity, 1e308, empty and oversized lists, unknown,
duplicated and body-only parameters, very long query strings and bodies; and the
limits on work: sizes, the albedo's worst-case cost, and the time budget."""
from __future__ import annotations

import json
import warnings

import numpy as np
import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.views import VIEWS
from app.views.schemas import ModelQuery
from app.config import Settings
from tests import heavy_pool
from tests.budget import settings_for_tests
from app.integrate.albedo import albedo, albedo_average, max_evaluations
from app.main import create_app
from app.model import make_spec
from tests.finite import finite_json

BAD_NUMBERS = ["nan", "NaN", "inf", "-inf", "Infinity", "-Infinity", "1e308", "-1e308", "1e309",
               "", "abc", "0x10", "1,5"]
ROUTES = [f"/api/v1/{name}" for name in VIEWS] + [f"/api/v1/figures/{name}" for name in VIEWS]


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(settings_for_tests()))


def _detail(r):
    d = r.json()["detail"]
    assert isinstance(d, list) and d, d
    return d


def _numeric_fields(model) -> list[str]:
    """Query fields of a view that take numbers (scalars or lists)."""
    out = []
    for name, field in model.model_fields.items():
        text = repr(field.annotation)
        if "float" in text or "int" in text:
            out.append(name)
    return out


def _no_nan_or_inf(r):
    finite_json(r.content)


def _own_fields(model, names: list[str]) -> list[str]:
    """The fields a view's query adds to the shared model query, or redefines."""
    shared = ModelQuery.model_fields
    return [n for n in names if n not in shared or repr(model.model_fields[n]) != repr(shared[n])]


@pytest.mark.parametrize("view", list(VIEWS))
def test_every_numeric_parameter_refuses_non_finite_and_huge(client, view):
    """NaN, ±inf, 1e308 (and past float range), empty, text: 422 naming the parameter,
    for every numeric parameter of the view's data and figure routes. The shared model
    parameters (one pydantic model behind every route) on the first view; each other view
    its own parameters and any shared one it redefines."""
    v = VIEWS[view]
    for route, model in ((f"/api/v1/{view}", v.query), (f"/api/v1/figures/{view}", v.figure_query)):
        names = _numeric_fields(model)
        for name in (names if view == next(iter(VIEWS)) else _own_fields(model, names)):
            for bad in BAD_NUMBERS:
                r = client.get(route, params={name: bad})
                if r.status_code == 200:
                    # only a number inside the range may pass ("1,5" for a list)
                    assert bad == "1,5", (route, name, bad)
                    _no_nan_or_inf(r)
                    continue
                assert r.status_code == 422, (route, name, bad, r.status_code, r.text)
                assert any(name in e["loc"] for e in _detail(r)), (route, name, bad, r.text)


@pytest.mark.parametrize("route", ROUTES + ["/api/v1/eval"])
def test_unknown_parameter(client, route):
    r = client.get(route, params={"alpah": "0.3"})
    assert r.status_code == 422 and any("alpah" in e["loc"] for e in _detail(r)), r.text


@pytest.mark.parametrize("route", ROUTES + ["/api/v1/eval"])
def test_scalar_given_twice_is_refused(client, route):
    r = client.get(f"{route}?alpha=0.1&alpha=0.2")
    assert r.status_code == 422
    (e,) = _detail(r)
    assert e["loc"] == ["query", "alpha"] and "given 2 times" in e["msg"], e
    # the same name spelled with a percent-escape is the same parameter
    r = client.get(f"{route}?alpha=0.1&%61lpha=0.2")
    assert r.status_code == 422 and _detail(r)[0]["loc"] == ["query", "alpha"]


def test_list_parameters_may_repeat(client):
    """Repeating a list parameter is the standard way to send a list."""
    a = client.get("/api/v1/eval?theta_i_deg=10&theta_i_deg=20&theta_o_deg=30")
    b = client.get("/api/v1/eval?theta_i_deg=10,20&theta_o_deg=30")
    assert a.status_code == 200 and a.json() == b.json()
    assert client.get("/api/v1/albedo?mu=0.5&mu=1").status_code == 200


def test_post_eval_takes_no_query_parameters(client):
    """POST /eval reads the body: a query parameter would be silently ignored, so it is
    refused, naming it."""
    r = client.post("/api/v1/eval?alpha=0.5", json={"theta_i_deg": [10.0]})
    assert r.status_code == 422
    assert _detail(r)[0]["loc"] == ["query", "alpha"] and "body" in _detail(r)[0]["msg"]


@pytest.mark.parametrize("bad", ["nan", "inf", "-inf", "1e308", ""])
def test_list_elements_are_checked(client, bad):
    r = client.get(f"/api/v1/eval?theta_i_deg=10,{bad},20")
    assert r.status_code == 422 and any("theta_i_deg" in e["loc"] for e in _detail(r)), r.text
    r = client.get(f"/api/v1/albedo?mu=0.5,{bad}")
    assert r.status_code == 422 and any("mu" in e["loc"] for e in _detail(r)), r.text


def test_post_body_non_finite_and_malformed(client):
    for body in ('{"theta_i_deg": [NaN]}', '{"theta_i_deg": [Infinity]}', '{"alpha": 1e999}',
                 '{"theta_i_deg": [1e308]}'):
        r = client.post("/api/v1/eval", content=body, headers={"content-type": "application/json"})
        assert r.status_code == 422, (body, r.text)
    r = client.post("/api/v1/eval", content=b"\xff\xfe{", headers={"content-type": "application/json"})
    assert r.status_code in (400, 422) and "detail" in r.json()
    r = client.post("/api/v1/eval", json={"theta_i_deg": []})
    assert r.status_code == 422


def test_empty_and_oversized_lists():
    small = TestClient(create_app(Settings(max_query_list=4, max_batch=8, max_albedo_points=5)))
    assert small.get("/api/v1/eval?theta_i_deg=").status_code == 422
    r = small.get("/api/v1/eval?theta_i_deg=1,2,3,4,5")
    assert r.status_code == 422 and "BRDF_MAX_QUERY_LIST" in _detail(r)[0]["msg"]
    r = small.post("/api/v1/eval", json={"theta_i_deg": [1.0] * 9})
    assert r.status_code == 413 and "BRDF_MAX_BATCH" in _detail(r)[0]["msg"]
    r = small.get("/api/v1/albedo?mu=" + ",".join(["0.5"] * 6))
    assert r.status_code == 422 and "BRDF_MAX_ALBEDO_POINTS" in _detail(r)[0]["msg"]


def test_very_long_query_string_is_414_naming_the_limit():
    c = TestClient(create_app(Settings(max_query_bytes=1000)))
    r = c.get("/api/v1/eval?theta_i_deg=" + ",".join(["45.125"] * 200))
    assert r.status_code == 414
    (e,) = _detail(r)
    assert "BRDF_MAX_QUERY_BYTES" in e["msg"] and "POST" in e["msg"]
    assert c.get("/api/v1/eval?theta_i_deg=" + ",".join(["45.125"] * 100)).status_code == 200


def test_body_limit_with_and_without_content_length():
    c = TestClient(create_app(Settings(max_body_bytes=1000)))
    body = json.dumps({"theta_i_deg": [45.125] * 300}).encode()
    r = c.post("/api/v1/eval", content=body, headers={"content-type": "application/json"})
    assert r.status_code == 413 and "BRDF_MAX_BODY_BYTES" in _detail(r)[0]["msg"]

    def chunks():                       # no Content-Length: counted as it arrives
        for i in range(0, len(body), 100):
            yield body[i:i + 100]

    r = c.post("/api/v1/eval", content=chunks(), headers={"content-type": "application/json"})
    assert r.status_code == 413 and "BRDF_MAX_BODY_BYTES" in _detail(r)[0]["msg"]
    ok = json.dumps({"theta_i_deg": [45.0]}).encode()
    assert c.post("/api/v1/eval", content=ok, headers={"content-type": "application/json"}).status_code == 200


# ------------------------------------------------------------------ limits on the work

def test_albedo_worst_case_is_refused_up_front():
    c = TestClient(create_app(Settings(max_evaluations=25_000_000)))
    r = c.get("/api/v1/albedo?n=100")
    assert r.status_code == 422
    (e,) = _detail(r)
    assert e["loc"] == ["query", "n"] and "BRDF_MAX_EVALUATIONS" in e["msg"]
    assert c.get("/api/v1/albedo?n=2").status_code == 200


def test_max_evaluations_bounds_the_real_cost():
    """max_evaluations is an upper bound of what albedo + albedo_average really spend,
    even where every μ needs the highest order (tol at its floor, the sharpest
    anisotropic lobe) — else the up-front refusal would not bound the time."""
    for ndf in ("ggx", "beckmann"):
        brdf = make_spec(ndf=ndf, alpha=1e-4, alpha_y=1.0).brdf()
        mu = np.array([0.0, 0.3, 1.0])
        spent = albedo(brdf, mu, tol=1e-7).evaluations + albedo_average(brdf, tol=1e-7)[2]
        assert spent <= max_evaluations(brdf, mu.size), (ndf, spent, max_evaluations(brdf, mu.size))


def _heavy_pool_started():
    """Wait until this process's heavy-work pool has a started worker: a budget of a
    quarter second is meant to cut the refinement, not the worker's start (an earlier
    cut in this process replaced it; under load its start takes seconds and the request
    is rightly refused with a 503, test_heavy_pool.py)."""
    heavy_pool.started()


def test_time_budget_cuts_refinement_with_a_message():
    """With a budget too small for the refinement the answer comes back, marked
    incomplete, with the error of what was computed, a header, and no-store; with a
    large budget the same request completes (a cut answer is never cached)."""
    url = "/api/v1/albedo?n=33&tol=1e-7&alpha=1e-4&alpha_y=1"
    _heavy_pool_started()
    cut = TestClient(create_app(Settings(max_seconds=0.25))).get(url)   # the full answer takes ~1.4 s
    assert cut.status_code == 200
    data = cut.json()
    assert data["complete"] is False and "BRDF_MAX_SECONDS" in data["note"]
    assert "BRDF_MAX_SECONDS" in cut.headers["x-time-budget"]
    assert cut.headers["cache-control"] == "no-store"
    assert all(e is not None and e > 0 for e in data["E_error"])
    full = TestClient(create_app(Settings(max_seconds=600))).get(url).json()
    assert full["complete"] is True and "note" not in full
    assert full["evaluations"] > data["evaluations"]
    assert max(full["E_error"]) < max(data["E_error"])


def test_cut_figure_says_so_in_a_header():
    _heavy_pool_started()
    r = TestClient(create_app(Settings(max_seconds=0.25))).get(
        "/api/v1/figures/albedo?n=9&tol=1e-7&alpha=1e-4&alpha_y=1")
    assert r.status_code == 200 and "x-time-budget" in r.headers


def test_settings_from_environment_name_the_variable(monkeypatch):
    monkeypatch.setenv("BRDF_MAX_SECONDS", "2.5")
    monkeypatch.setenv("BRDF_MAX_QUERY_BYTES", "4096")
    s = Settings.from_env()
    assert s.max_seconds == 2.5 and s.max_query_bytes == 4096
    for name, raw in (("BRDF_MAX_SECONDS", "ten"), ("BRDF_MAX_CURVE_POINTS", "-1"),
                      ("BRDF_MAX_SECONDS", "nan"), ("BRDF_MAX_BATCH", "1.5")):
        monkeypatch.setenv(name, raw)
        with pytest.raises(ValueError, match=name):
            Settings.from_env()
        monkeypatch.delenv(name)
