"""Difference and fit in the data's channel when the model is coloured, every Fresnel
parameter available to the fit with what was held fixed said, a warning when the model
does not describe the data, a principled fit refused, overflowing data never reported
as converged, and ``max_points`` honoured on term data (issues 34 and 36).

The data are written from conductor models whose complex index is a material's own
per-channel index (app/materials' record), evaluated by the plain microfacet model with
fresnel=conductor: independent of the per-channel path under test.
"""
from __future__ import annotations

import io

import numpy as np
import pytest

from app.materials import material
from app.model import make_spec
from app.physics.vectors import direction_deg
from tests.datasets.conftest import app, client  # noqa: F401  (fixtures)

ALPHA = 0.2
GOLD = material("gold")


def _grid():
    ti, pi, to, po = np.meshgrid(np.linspace(0, 80, 9), np.arange(0, 360, 30.0), np.linspace(0, 80, 9),
                                 [0.0], indexing="ij")
    return [x.ravel() for x in (ti, pi, to, po)]


def _channel_f(c: int, angles, alpha=ALPHA) -> np.ndarray:
    """f of gold's channel c as a conductor model with that channel's (n, k)."""
    ti, pi, to, po = angles
    brdf = make_spec(ndf="ggx", alpha=alpha, fresnel="conductor", ior=max(GOLD["n"][c], 0.01),
                     k=GOLD["k"][c]).brdf()
    return brdf.f(direction_deg(ti, pi), direction_deg(to, po))


def _upload(client, columns: dict) -> str:
    out = io.StringIO()
    np.savetxt(out, np.column_stack(list(columns.values())), delimiter=",", fmt="%.17g",
               header=",".join(columns), comments="")
    res = client.post("/api/v1/datasets", content=out.getvalue().encode())
    assert res.status_code == 201, res.text
    return res.json()["id"]


@pytest.fixture(scope="module")
def gold_data(client):
    angles = _grid()
    cols = dict(zip(("theta_i_deg", "phi_i_deg", "theta_o_deg", "phi_o_deg"), angles))
    cols.update({f"f_{c}": _channel_f(k, angles) for k, c in enumerate("rgb") if k})
    cols["f_r"] = _channel_f(1, angles)          # red's n = 0 is outside the model's range
    return _upload(client, {k: cols[k] for k in ("theta_i_deg", "phi_i_deg", "theta_o_deg",
                                                  "phi_o_deg", "f_r", "f_g", "f_b")})


def test_difference_compares_the_models_channel_with_the_datas(client, gold_data):
    res = client.get(f"/api/v1/datasets/{gold_data}/difference",
                     params={"material": "gold", "alpha": ALPHA, "channel": "b", "max_points": 50000})
    assert res.status_code == 200, res.text
    assert abs(res.json()["max_relative_error"]) < 1e-9


def test_a_conductor_fit_frees_eta_and_kappa_and_warns_when_they_are_held(client, gold_data):
    held = client.post("/api/v1/fit", json={"data": gold_data, "model": {"fresnel": "conductor"},
                                            "free": ["alpha", "kd"], "channel": "b"}).json()
    assert set(held["held_fixed"]) >= {"ior", "k"}
    assert held["misfit"]["warning"] and held["misfit"]["relative_rms"] > held["misfit"]["threshold"]
    freed = client.post("/api/v1/fit", json={"data": gold_data, "model": {"fresnel": "conductor"},
                                             "free": ["alpha", "ior", "k", "kd"], "channel": "b"}).json()
    assert freed["params"]["alpha"] == pytest.approx(ALPHA, rel=1e-4)
    assert freed["params"]["ior"] == pytest.approx(GOLD["n"][2], rel=1e-3)
    assert freed["params"]["k"] == pytest.approx(GOLD["k"][2], rel=1e-3)
    assert freed["misfit"]["warning"] is None and "ior" not in freed["held_fixed"]


def test_a_fit_of_a_coloured_model_uses_the_channel(client, gold_data):
    out = client.post("/api/v1/fit", json={"data": gold_data, "model": {"material": "gold"},
                                           "free": ["alpha"], "channel": "b"}).json()
    assert out["params"]["alpha"] == pytest.approx(ALPHA, rel=1e-6)
    assert out["residual"] < 1e-8 and out["misfit"]["warning"] is None


def test_a_principled_fit_is_refused_with_a_422(client, gold_data):
    res = client.post("/api/v1/fit", json={"data": gold_data, "model": {"model": "principled"},
                                           "free": ["alpha"]})
    assert res.status_code == 422, res.text
    assert res.json()["detail"][0]["loc"][-1] == "model.model"


@pytest.mark.parametrize("measure", ["cosine", "relative", "log"])
def test_data_of_1e308_is_never_a_converged_fit_without_a_residual(client, measure):
    angles = _grid()
    data = _upload(client, {**dict(zip(("theta_i_deg", "phi_i_deg", "theta_o_deg", "phi_o_deg"), angles)),
                            "f": np.full(angles[0].size, 1e308)})
    out = client.post("/api/v1/fit", json={"data": data, "model": {}, "free": ["alpha", "kd"],
                                           "measure": measure, "seconds": 5})
    assert out.status_code == 200, out.text
    body = out.json()
    assert not (body["residual"] is None and body["converged"])
    assert body["misfit"]["warning"]


def test_max_points_bounds_the_difference_of_a_large_term_file(client):
    theta = np.linspace(0, 89.9, 300_000)
    data = _upload(client, {"theta_deg": theta, "D": np.cos(np.radians(theta)) ** 2 / np.pi})
    res = client.get(f"/api/v1/datasets/{data}/difference", params={"max_points": 10, "channel": "D"})
    assert res.status_code == 200, res.text
    assert res.json()["points"] == 10 and len(res.json()["data"]) == 10
