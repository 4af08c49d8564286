"""Hostile JSON bodies (app/api/http/strict.py): each a 4xx that names the field, never
a 500 and never a value taken for what it is not."""
from __future__ import annotations

import json
import warnings

import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.api.http.strict import MAX_JSON_DEPTH
from app.main import create_app
from tests.budget import settings_for_tests

JSON = {"content-type": "application/json"}
PAIR = {"theta_i_deg": [30], "phi_i_deg": [0], "theta_o_deg": [30], "phi_o_deg": [180]}


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(settings_for_tests()))


@pytest.mark.parametrize("path", ["/api/v1/eval", "/api/v1/lut/check?kind=kc_E", "/api/v1/batch",
                                  "/api/v1/fit", "/api/v1/figures/lobe"])
@pytest.mark.parametrize("depth", [1000, 100_000, MAX_JSON_DEPTH + 2])
def test_deep_nesting_is_a_4xx_naming_the_body(client, path, depth):
    for body in ("[" * depth + "]" * depth, '{"a":' * depth + "1" + "}" * depth):
        r = client.post(path, content=body, headers=JSON)
        assert r.status_code == 422, (path, r.status_code, r.text[:200])
        detail = r.json()["detail"][0]
        assert detail["loc"] == ["body"] and "deep" in detail["msg"]


@pytest.mark.parametrize("constant", ["NaN", "Infinity", "-Infinity"])
def test_non_finite_numbers_are_located(client, constant):
    body = json.dumps(PAIR)[:-1] + f', "alpha": {constant}}}'
    r = client.post("/api/v1/eval", content=body, headers=JSON)
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "alpha"], r.text
    inside = json.dumps(PAIR).replace('"theta_o_deg": [30]', f'"theta_o_deg": [30, 40, {constant}]')
    r = client.post("/api/v1/eval", content=inside, headers=JSON)
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "theta_o_deg", 2], r.text
    assert constant in r.json()["detail"][0]["msg"]


def test_a_number_written_as_a_string_is_refused(client):
    r = client.post("/api/v1/eval", json={**PAIR, "alpha": "0.3"})
    assert r.status_code == 422, r.text
    detail = r.json()["detail"][0]
    assert detail["loc"] == ["body", "alpha"] and "'0.3'" in detail["msg"]
    r = client.post("/api/v1/eval", json={**PAIR, "theta_i_deg": [30, "45"]})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "theta_i_deg", 1]
    # a boolean is no number anywhere, a compared model's parameter included
    r = client.post("/api/v1/figures/lobe", json={"models": [{"alpha": 0.2}, {"alpha": True}]})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["body", "models", 1, "alpha"], r.text


def test_the_same_numbers_as_numbers_pass(client):
    assert client.post("/api/v1/eval", json={**PAIR, "alpha": 0.3}).status_code == 200
    assert client.post("/api/v1/figures/lobe", json={"models": [{"alpha": 0.2}, {"alpha": 0.3}]}).status_code == 200
