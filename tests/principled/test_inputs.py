"""The principled model takes what it declares (issue 34): roughness over [0, 1] (the
microfacet form still starts at 0.01), base_color as r,g,b, a JSON list or #rrggbb, and a
helpful 422 for anything else."""
from __future__ import annotations

import warnings

import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.main import create_app
from tests.budget import settings_for_tests

GEOMETRY = {"theta_i_deg": 30.0, "phi_i_deg": 0.0, "theta_o_deg": 40.0, "phi_o_deg": 180.0}


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(settings_for_tests()))


def test_declared_roughness_range_starts_at_zero(client):
    declared = client.get("/api/v1/principled").json()
    text = str(declared)
    assert "roughness" in text
    for path, extra in (("/api/v1/eval", {}), ("/api/v1/lobe", {"n": 32}), ("/api/v1/sphere", {"n": 32})):
        r = client.get(path, params={"model": "principled", "roughness": 0.0, **extra})
        assert r.status_code == 200, (path, r.text)


def test_roughness_zero_is_the_floor_alpha_not_a_delta(client):
    # r = 0 and r = √ALPHA_MIN-equivalent small roughness both draw GGX at the named floor
    # α = 0.001 (disney.brdf's max(.001, r²)): f is finite and the same at r = 0 and r = 0.01
    # where r² = 1e-4 < 0.001 too
    a = client.get("/api/v1/eval", params={"model": "principled", "roughness": 0.0, **GEOMETRY,
                                          "quantities": "f"}).json()["f"][0]
    b = client.get("/api/v1/eval", params={"model": "principled", "roughness": 0.01, **GEOMETRY,
                                          "quantities": "f"}).json()["f"][0]
    assert a is not None and b is not None


def test_microfacet_roughness_still_names_its_range(client):
    r = client.get("/api/v1/lobe", params={"roughness": 0.0})
    assert r.status_code == 422
    assert "roughness" in r.text and "0.01" in r.text


@pytest.mark.parametrize("form", ["1,0,0", "#ff0000", "#f00", "#FF0000"])
def test_base_color_forms_agree_in_a_query(client, form):
    # #ff0000 decodes (sRGB curve: 1 → 1, 0 → 0) to linear 1,0,0
    want = client.get("/api/v1/eval", params={"model": "principled", "base_color": "1,0,0", **GEOMETRY,
                                             "quantities": "f_rgb"}).json()["f_rgb"]
    r = client.get("/api/v1/eval", params={"model": "principled", "base_color": form, **GEOMETRY,
                                          "quantities": "f_rgb"})
    assert r.status_code == 200, r.text
    assert r.json()["f_rgb"] == want


def test_hex_is_decoded_by_the_srgb_curve(client):
    # #808080: 128/255 = 0.50196 encoded → ((0.50196 + 0.055)/1.055)^2.4 = 0.21586 linear
    a = client.get("/api/v1/eval", params={"model": "principled", "base_color": "#808080", **GEOMETRY,
                                          "quantities": "f_rgb"}).json()["f_rgb"]
    b = client.get("/api/v1/eval", params={"model": "principled", "base_color": "0.21586,0.21586,0.21586",
                                          **GEOMETRY, "quantities": "f_rgb"}).json()["f_rgb"]
    assert a[0] == pytest.approx(b[0], rel=1e-4)


def test_base_color_as_a_json_list(client):
    body = {"model": "principled", "quantities": ["f_rgb"], **{k: [v] for k, v in GEOMETRY.items()}}
    r = client.post("/api/v1/eval", json={**body, "base_color": [1, 0, 0]})
    assert r.status_code == 200, r.text
    s = client.post("/api/v1/eval", json={**body, "base_color": "1,0,0"})
    assert r.json() == s.json()


@pytest.mark.parametrize("bad", ["red", "#zz0000", "1,2", "#12345"])
def test_bad_base_color_says_which_forms_work(client, bad):
    r = client.get("/api/v1/eval", params={"model": "principled", "base_color": bad})
    assert r.status_code == 422
    assert "base_color" in r.text and "#rrggbb" in r.text and "r,g,b" in r.text
