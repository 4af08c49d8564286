"""The diffuse term in the albedo (every method adds its own albedo, not kd) and in /eval."""
from __future__ import annotations

import numpy as np
import pytest
from fastapi.testclient import TestClient

from app.integrate.methods import albedo_by
from app.main import create_app
from tests.budget import settings_for_tests
from app.model import make_spec

from .test_models import _midpoint_albedo


@pytest.mark.parametrize("method", ["quadrature", "table"])
def test_albedo_is_specular_plus_diffuse(method):
    mu = np.array([0.2, 0.7])
    spec = dict(alpha=0.36, fresnel="schlick", f0=0.04)
    specular = albedo_by(make_spec(kd=0.0, **spec).brdf(), mu, method=method)
    total = albedo_by(make_spec(kd=0.6, diffuse="burley", **spec).brdf(), mu, method=method)
    # Burley takes r = √α = 0.6 from the specular roughness
    s = dict(alpha=0.36, sigma=0.0, diffuse_roughness=0.0)
    diffuse = [_midpoint_albedo("burley", s, 0.6, t) for t in np.arccos(mu)]
    tol = np.max(specular["E_error"] + total["E_error"]) + 3e-5
    np.testing.assert_allclose(total["E"], specular["E"] + diffuse, atol=tol)
    want_avg = specular["E_avg"] + 0.6 * make_spec(kd=1.0, diffuse="burley", **spec).brdf().diffuse.albedo_avg(1.0)[0]
    assert abs(total["E_avg"] - want_avg) < specular["E_avg_error"] + total["E_avg_error"] + 1e-5


def test_eval_answers_f_diffuse():
    with TestClient(create_app(settings_for_tests())) as client:
        r = client.get("/api/v1/eval", params={"diffuse": "oren_nayar", "sigma": 0.5, "kd": 0.5,
                                               "theta_i_deg": 30, "theta_o_deg": 60, "phi_o_deg": 0})
        assert r.status_code == 200, r.text
        body = r.json()
        s2 = 0.25
        A, B = 1 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09)
        want = 0.5 / np.pi * (A + B * np.sin(np.radians(60)) * np.tan(np.radians(30)))
        assert abs(body["f_diffuse"][0] - want) < 1e-12
        assert body["f"][0] > body["f_diffuse"][0]
        bad = client.get("/api/v1/eval", params={"diffuse": "oren_nayar", "sigma": 2.0})
        assert bad.status_code == 422 and "sigma" in bad.text
        wrong = client.get("/api/v1/eval", params={"sigma": 0.5})
        assert wrong.status_code == 422 and "oren_nayar" in wrong.text
