"""A shader's dump against the reference: two classic bugs, each shown wrong with its
largest error where the bug predicts it (GET /api/v1/datasets/{id}/difference)."""
import io
import math

import numpy as np
import pytest

from . import known

ALPHA = 0.3


def dump(f) -> bytes:
    """A samples CSV of f(l, v) on θ_i, θ_o ∈ 0..80°, φ_i = 0, φ_o every 45°."""
    rows = []
    for ti in range(0, 81, 10):
        for to in range(0, 81, 10):
            for po in range(0, 360, 45):
                l = np.array([math.sin(math.radians(ti)), 0.0, math.cos(math.radians(ti))])
                v = np.array([math.sin(math.radians(to)) * math.cos(math.radians(po)),
                              math.sin(math.radians(to)) * math.sin(math.radians(po)),
                              math.cos(math.radians(to))])
                rows.append((ti, 0, to, po, float(f(l, v))))
    out = io.StringIO()
    np.savetxt(out, rows, fmt="%.17g", delimiter=",", comments="",
               header="theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f")
    return out.getvalue().encode()


def G2(l, v, alpha):
    def Lambda(w):
        tan2 = (1 - w[2] ** 2) / w[2] ** 2
        return (-1 + math.sqrt(1 + alpha ** 2 * tan2)) / 2
    return 1 / (1 + Lambda(l) + Lambda(v))


REFERENCE = {"ndf": "ggx", "alpha": ALPHA, "f0": 0.04, "kd": 0.0}


def difference(client, content):
    data_id = client.post("/api/v1/datasets", content=content).json()["id"]
    response = client.get(f"/api/v1/datasets/{data_id}/difference", params=REFERENCE)
    assert response.status_code == 200, response.text
    return response.json()


def test_a_missing_one_over_4_cos_cos_peaks_at_normal_incidence(client):
    """f·4(n·l)(n·v): (data − model)/model = 4 μ_l μ_v − 1 everywhere, largest (+3) where
    both directions are normal."""
    out = difference(client, dump(lambda l, v: known.ggx_f(l, v, ALPHA, 0.04, 0.0) * 4 * l[2] * v[2]))
    at = out["at"]
    predicted = 4 * np.cos(np.radians(at["theta_i_deg"])) * np.cos(np.radians(at["theta_o_deg"])) - 1
    np.testing.assert_allclose(out["relative_error"], predicted, atol=1e-9)
    assert out["max_relative_error"] == pytest.approx(3.0, abs=1e-9)
    assert out["where"]["theta_i_deg"] == 0 and out["where"]["theta_o_deg"] == 0


def test_d_and_g_on_different_alphas_peak_at_grazing(client):
    """D at α = 0.3 but G2 at α = 0.6: the masking is overstated, worst where both
    directions are most grazing (80°), by G2(0.6)/G2(0.3) − 1 there."""
    def wrong(l, v):
        return known.ggx_f(l, v, ALPHA, 0.04, 0.0) * G2(l, v, 0.6) / G2(l, v, ALPHA)
    out = difference(client, dump(wrong))
    assert out["where"]["theta_i_deg"] == pytest.approx(80) and out["where"]["theta_o_deg"] == pytest.approx(80)
    grazing = np.array([math.sin(math.radians(80)), 0, math.cos(math.radians(80))])
    assert out["max_relative_error"] == pytest.approx(G2(grazing, grazing, 0.6) / G2(grazing, grazing, ALPHA) - 1,
                                                      rel=1e-9)
    assert out["max_relative_error"] < -0.3


def test_the_right_implementation_is_not_shown_wrong(client):
    out = difference(client, dump(lambda l, v: known.ggx_f(l, v, ALPHA, 0.04, 0.0)))
    assert abs(out["max_relative_error"]) < 1e-9


def test_the_relative_error_is_stated_only_where_it_is_a_number():
    """Data at the ends of the floats against GGX: (data − model)/model where it is a float,
    null where it is not — data of 10³⁰⁸ against a model of ~0.1 (10³⁰⁹ is no float), or a
    model of 0 (Schlick F₀ = F₉₀ = 0, no diffuse) against any data. Checked in exact decimal arithmetic;
    the largest and the rms are those of the stated values, and no overflow is computed (a
    RuntimeWarning is an error here: the relative error overflowed, and a model of 0 read
    as a relative error of 0.0, a perfect match)."""
    import warnings
    from decimal import Decimal, getcontext

    from fastapi.testclient import TestClient

    from app.main import create_app
    from tests.budget import settings_for_tests

    getcontext().prec = 50
    half_max = Decimal(np.finfo(float).max) / 2
    content = (b"theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n30,0,30,180,1e308\n45,0,20,90,1e-300\n"
               b"60,0,60,180,5e307\n30,0,90,0,1.0\n10,0,10,180,3.0\n")
    with TestClient(create_app(settings_for_tests())) as client, warnings.catch_warnings():
        warnings.simplefilter("error", RuntimeWarning)
        out = difference(client, content)
        data_id = client.post("/api/v1/datasets", content=content).json()["id"]
        black = client.get(f"/api/v1/datasets/{data_id}/difference", params={**REFERENCE, "f0": 0.0, "f90": 0.0})
    assert black.status_code == 200, black.text
    black = black.json()
    assert max(black["model"]) == 0.0 and black["relative_error"] == [None] * 5
    assert black["max_relative_error"] is None and black["rms_relative_error"] is None
    stated = {}
    for i, (d, m, r) in enumerate(zip(out["data"], out["model"], out["relative_error"])):
        exact = (Decimal(d) - Decimal(m)) / Decimal(m) if m > 0 else None
        if exact is None or abs(exact) > half_max:
            assert r is None, (i, d, m, r)
        else:
            assert r == pytest.approx(float(exact), rel=1e-12), (i, d, m, r)
            stated[i] = exact
    assert {1, 4} <= set(stated) and not {0, 2} & set(stated)     # 10³⁰⁸ / 0.1: no float
    largest = max(stated.values(), key=abs)
    assert out["max_relative_error"] == pytest.approx(float(largest), rel=1e-12)
    rms = (sum(x * x for x in stated.values()) / len(stated)).sqrt()
    assert out["rms_relative_error"] == pytest.approx(float(rms), rel=1e-12)
