"""Extreme angles and roughnesses: finite values, documented divergences, no NaN, no
floating-point warnings, continuity into the limits (docs/conventions.md).

Documented non-finite values (masking.py, brdf.py, ndf/base.py):
* Λ(ω) = +inf at μ = 0;
* f = +inf under the height-correlated G2 where both l and v graze (μl = μv = 0),
  h exists and D(h)F > 0.
Everything else is finite, never NaN.

Floating-point state: divide, overflow and invalid raise; warnings are errors. Underflow
is left at numpy's default (ignored): exp(−tan²θ/α²) → 0 for Beckmann at small α is the
correct value, not an error.
"""
from __future__ import annotations

import numpy as np
import pytest

from app.physics.brdf import QUANTITIES
from app.physics.masking import G1, MASKINGS
from app.physics.vectors import direction_deg
from tests.strict import strict

from .conftest import make_ndf, make_brdf

THETAS = [0.0, 1e-7, 45.0, 89.999, 89.9999, 90.0]
PHIS = [0.0, 37.0, 90.0, 180.0, 270.0]
ALPHAS = [1e-4, 1e-3, 0.5, 1.0]
SMITH = MASKINGS["smith"]


def _upper_dirs():
    return np.array([direction_deg(t, p) for t in THETAS for p in PHIS])


def _brdf_params():
    for a in ALPHAS:
        for ay in sorted({a, 1.0, 1e-4}):
            yield a, ay


BRDF_PARAMS = list(_brdf_params())


def _check_outputs(brdf, l, v, out, g2):
    for q in QUANTITIES:
        assert not np.any(np.isnan(out[q])), q
    for q in ("D", "G1_i", "G1_o", "G2", "F"):
        assert np.all(np.isfinite(out[q])), q
    both_graze = (l[:, 2] == 0.0) & (v[:, 2] == 0.0)
    h_exists = np.linalg.norm(l + v, axis=-1) > 1e-12
    diverges = both_graze & h_exists & (out["D"] * out["F"] > 0)
    if g2 == "height_correlated":
        assert np.all(out["f"][diverges] == np.inf)
        assert np.all(np.isfinite(out["f"][~diverges]))
    else:
        assert np.all(np.isfinite(out["f"]))
    assert np.all(out["f"] >= 0.0)
    assert np.all((out["G2"] >= 0) & (out["G2"] <= 1))
    assert np.all((out["G1_i"] >= 0) & (out["G1_i"] <= 1))


@pytest.mark.parametrize("ax, ay", BRDF_PARAMS, ids=[f"ax{a:g}-ay{b:g}" for a, b in BRDF_PARAMS])
@pytest.mark.parametrize("g2", ["separable", "height_correlated"])
def test_all_pairs_of_extreme_directions(ndf_name, ax, ay, g2):
    """Every pair (l, v) of the closed upper hemisphere built from θ ∈ THETAS, φ ∈ PHIS:
    l = v, both grazing (also opposite: l = −v on the horizon), one grazing, normal."""
    dirs = _upper_dirs()
    l = np.repeat(dirs, len(dirs), axis=0)
    v = np.tile(dirs, (len(dirs), 1))
    brdf = make_brdf(ndf_name, ax, ay, g2=g2, fresnel="schlick", kd=0.1)
    with strict():
        out = brdf.evaluate(l, v, QUANTITIES)
    _check_outputs(brdf, l, v, out, g2)
    # l = −v on the horizon: no half vector, no specular term
    opposite = np.all(np.abs(l + v) < 1e-15, axis=-1)
    assert opposite.any()
    assert np.all(out["f"][opposite] == pytest.approx(0.1 / np.pi, rel=1e-15, abs=0))


@pytest.mark.parametrize("theta_v", THETAS)
@pytest.mark.parametrize("g2", ["separable", "height_correlated"])
@pytest.mark.parametrize("alpha", [1e-4, 0.5, 1.0])
def test_l_opposite_v(ndf_name, alpha, g2, theta_v):
    """l = −v: no half vector; f = 0 (l below the horizon unless both graze, then only
    kd/π with kd = 0 here) — finite, no NaN, no warning."""
    v = np.stack([direction_deg(theta_v, p) for p in PHIS])
    l = -v
    brdf = make_brdf(ndf_name, alpha, g2=g2, fresnel="schlick")
    with strict():
        out = brdf.evaluate(l, v, QUANTITIES)
    for q in QUANTITIES:
        assert np.all(np.isfinite(out[q])), q
    assert np.all(out["f"] == 0.0)
    assert np.all(out["G2"] == 0.0)


@pytest.mark.parametrize("ax, ay", BRDF_PARAMS, ids=[f"ax{a:g}-ay{b:g}" for a, b in BRDF_PARAMS])
def test_Lambda_and_G1_at_extremes(ndf_name, ax, ay):
    """μΛ finite and ≥ 0 everywhere in the closed upper hemisphere; Λ finite except
    +inf exactly at μ = 0; G1 ∈ [0, 1], 0 at μ = 0, 1 at θ = 0."""
    ndf = make_ndf(ndf_name, ax, ay)
    dirs = _upper_dirs()
    with strict():
        ml = ndf.mu_Lambda(dirs)
        lam = ndf.Lambda(dirs)
        g1 = G1(dirs[:, 2], SMITH.mu_Lambda(ndf, dirs))
    assert np.all(np.isfinite(ml)) and np.all(ml >= 0)
    graze = dirs[:, 2] == 0.0
    assert np.all(lam[graze] == np.inf)
    assert np.all(np.isfinite(lam[~graze])) and np.all(lam[~graze] >= 0)
    assert np.all(g1[graze] == 0.0)
    assert np.all(g1[dirs[:, 2] == 1.0] == 1.0)
    assert np.all((g1 >= 0) & (g1 <= 1))


@pytest.mark.parametrize("ax, ay", [(1e-4, 1e-4), (1e-3, 1e-3), (0.5, 0.5), (1.0, 1.0), (1e-3, 1.0)])
def test_D_at_extreme_half_vectors(ndf_name, ax, ay):
    """D finite and ≥ 0 at θ_m ∈ THETAS; continuous at the horizon: D(90° − 1e-9) close
    to D(90°) (GGX: the finite limit 1/(π αx αy q⁴); Beckmann: 0)."""
    ndf = make_ndf(ndf_name, ax, ay)
    m = _upper_dirs()
    with strict():
        D = ndf.D(m)
        d90 = ndf.D(np.stack([direction_deg(90.0, p) for p in PHIS]))
        d_near = ndf.D(np.stack([direction_deg(90.0 - 1e-9, p) for p in PHIS]))
    assert np.all(np.isfinite(D)) and np.all(D >= 0)
    # Absolute tolerance relative to the peak: Blinn-Phong vanishes at the horizon like
    # cos^{α_p}θ (3.6e-65 at 1e-9° above it for α = 0.5), a power, not exponentially.
    peak = float(ndf.D(np.array([0.0, 0.0, 1.0])))
    np.testing.assert_allclose(d_near, d90, rtol=1e-6, atol=max(1e-300, 1e-40 * peak))


# ------------------------------------------------------------------------- continuity

DELTA = 1e-9   # degrees below the horizon angle


@pytest.mark.parametrize("alpha", ALPHAS)
@pytest.mark.parametrize("phi", [0.0, 37.0, 90.0])
def test_G1_continuous_at_horizon(ndf_name, alpha, phi):
    """G1(90° − 1e-9°) → G1(90°) = 0: G1 ≈ μ/μΛ(0) with μ = 1.7e-11 and μΛ(0) ≥ α_min/(2√π)
    (test_masking.test_G1_limits), so G1 ≤ 2√π μ/α_min < 4 μ/α_min."""
    ndf = make_ndf(ndf_name, alpha, 0.5 * alpha)
    w90, wn = direction_deg(90.0, phi), direction_deg(90.0 - DELTA, phi)
    with strict():
        g90 = float(G1(w90[2], SMITH.mu_Lambda(ndf, w90)))
        gn = float(G1(wn[2], SMITH.mu_Lambda(ndf, wn)))
    assert g90 == 0.0
    assert 0.0 < gn <= 4.0 * wn[2] / (0.5 * alpha)


@pytest.mark.parametrize("g2", ["separable", "height_correlated"])
@pytest.mark.parametrize("alpha", [1e-3, 0.5, 1.0])
@pytest.mark.parametrize("theta_v, phi_l", [(0.0, 0.0), (45.0, 180.0), (60.0, 90.0), (89.0, 200.0)])
def test_f_and_G2_continuous_one_grazing(ndf_name, alpha, g2, theta_v, phi_l):
    """One direction grazing: V = G2/(4 μl μv) tends to a finite constant, so f at
    θl = 90° − 1e-9° is close to f at 90° (relative 1e-6); G2(90°) = 0 and G2 just above
    is small. Also symmetric in l ↔ v."""
    brdf = make_brdf(ndf_name, alpha, g2=g2, fresnel="schlick")
    v = direction_deg(theta_v, 0.0)
    l90, ln = direction_deg(90.0, phi_l), direction_deg(90.0 - DELTA, phi_l)
    with strict():
        o90 = brdf.evaluate(l90, v, ("f", "G2"))
        on = brdf.evaluate(ln, v, ("f", "G2"))
        r90 = brdf.evaluate(v, l90, ("f",))
    assert np.isfinite(o90["f"]) and np.isfinite(on["f"])
    assert float(on["f"]) == pytest.approx(float(o90["f"]), rel=1e-6, abs=1e-300)
    assert float(r90["f"]) == pytest.approx(float(o90["f"]), rel=1e-12, abs=1e-300)
    assert float(o90["G2"]) == 0.0
    assert 0.0 <= float(on["G2"]) <= 1e-6


@pytest.mark.parametrize("alpha", [1e-3, 0.5, 1.0])
@pytest.mark.parametrize("dphi", [0.0, 37.0, 90.0])
def test_both_grazing(ndf_name, alpha, dphi):
    """Both grazing: separable V = 1/(4 μlΛl μvΛv) is finite and continuous; the
    height-correlated f is +inf at 90° where D(h) > 0 and grows without bound (finite)
    as θ → 90°."""
    l90, v90 = direction_deg(90.0, dphi), direction_deg(90.0, 0.0)
    sep = make_brdf(ndf_name, alpha, g2="separable")
    hc = make_brdf(ndf_name, alpha, g2="height_correlated")
    with strict():
        D = float(sep.evaluate(l90, v90, ("D",))["D"])
        s90 = float(sep.f(l90, v90))
        sn = float(sep.f(direction_deg(90.0 - DELTA, dphi), direction_deg(90.0 - DELTA, 0.0)))
        h90 = float(hc.f(l90, v90))
        hs = [float(hc.f(direction_deg(90.0 - d, dphi), direction_deg(90.0 - d, 0.0)))
              for d in (1e-3, 1e-6, DELTA)]
    assert np.isfinite(s90)
    # abs 1e-40: where D(h) vanishes at the horizon as a power (Blinn-Phong, cos^{α_p}θ)
    # f at 1e-9° above it is ~1e-64, not 0.
    assert sn == pytest.approx(s90, rel=1e-6, abs=1e-40)
    if D > 0:
        assert h90 == np.inf
        assert all(np.isfinite(hs)) and hs[0] < hs[1] < hs[2]
    else:
        assert h90 == 0.0
