"""Issue 11's own reproductions, as a user sends them: the lobe at α = 0.001 and 1e-4 with
θ_i = 45.5° (1° steps of θ_o drew 17.3 and 0.19 sr⁻¹ where f reaches 6.9e3 and 6.9e5),
and the 3-D lobe on the anisotropic ridge (α = 0.05 × 0.5, φ_i = 30°, θ_i = 50°), which
aliased into a sawtooth. The reference is f at the mirror direction from /eval."""
from __future__ import annotations

import numpy as np
import pytest


def _get(client, url: str) -> dict:
    r = client.get(url)
    assert r.status_code == 200, r.text
    return r.json()


@pytest.mark.parametrize("alpha", [0.001, 0.0001])
def test_lobe_reaches_its_peak_between_whole_degrees(client, alpha):
    lobe = _get(client, f"/api/v1/lobe?alpha={alpha}&theta_i_deg=45.5")
    mirror = _get(client, f"/api/v1/eval?alpha={alpha}&theta_i_deg=45.5&phi_i_deg=0"
                          "&theta_o_deg=45.5&phi_o_deg=180&quantities=f")["f"][0]
    drawn = max(v for v in lobe["f"] if v is not None)
    assert drawn >= 0.99 * mirror, (drawn, mirror)
    assert lobe["peak"]["f_drawn_max"] == pytest.approx(drawn, rel=1e-12)
    assert lobe["peak"]["f_true_max"] >= mirror * (1 - 1e-9)
    assert lobe["peak"]["relative_error"] < 0.01
    assert lobe["peak"]["theta_o_deg"] == pytest.approx(45.5, abs=0.05)


def test_lobe3d_on_the_anisotropic_ridge_is_drawn_within_tolerance(client):
    """Between its nodes the drawn surface is bilinear: at each cell centre f (from /eval)
    must be within 1 % of the surface's peak of that interpolation."""
    q = "alpha=0.05&alpha_y=0.5&phi_i_deg=30&theta_i_deg=50"
    grid = _get(client, f"/api/v1/lobe3d?{q}")
    theta, phi = np.asarray(grid["theta_deg"]), np.asarray(grid["phi_deg"])
    F = np.asarray(grid["f"], dtype=float)
    tc, pc = 0.5 * (theta[:-1] + theta[1:]), 0.5 * (phi[:-1] + phi[1:])
    T, P = np.meshgrid(tc, pc, indexing="ij")
    body = {"alpha": 0.05, "alpha_y": 0.5, "theta_i_deg": [50.0], "phi_i_deg": [30.0],
            "theta_o_deg": T.ravel().tolist(), "phi_o_deg": P.ravel().tolist(), "quantities": ["f"]}
    r = client.post("/api/v1/eval", json=body)
    assert r.status_code == 200, r.text
    centre = np.asarray(r.json()["f"], dtype=float).reshape(T.shape)
    bilinear = 0.25 * (F[:-1, :-1] + F[1:, :-1] + F[:-1, 1:] + F[1:, 1:])
    assert np.nanmax(np.abs(centre - bilinear)) <= 0.01 * np.nanmax(F)
    assert grid["resolution"]["converged"] and grid["peak"]["relative_error"] < 0.01
