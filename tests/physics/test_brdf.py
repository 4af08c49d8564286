"""The assembled BRDF: weak white furnace, reciprocity, composition and Fresnel.

f(l, v) = kd/π + D(h) F(v·h) G2(l, v) / (4 |n·l| |n·v|), h = (l+v)/‖l+v‖
(docs/conventions.md §5; Walter et al. 2007 eq. 20; Heitz 2014 eq. 4).
"""
from __future__ import annotations

import numpy as np
import pytest

from app.physics.fresnel import FRESNELS
from app.physics.vectors import direction_deg

from .conftest import gauss_on, l_sphere_rule, make_brdf, random_upper_directions

FURNACE_VIEWS_DEG = [(0.0, 0.0), (40.0, 23.0), (80.0, 160.0)]


@pytest.mark.parametrize("view_deg", FURNACE_VIEWS_DEG, ids=lambda t: f"v{t[0]:g}-{t[1]:g}")
def test_weak_white_furnace(ndf_name, alphas, view_deg):
    """∫_{S²} D(h) G1(v) / (4 |n·v|) dl = 1 over the FULL sphere of l (Heitz 2014 eq. 19,
    "weak white furnace test"; docs/identities.md §4), h = (l+v)/‖l+v‖.

    Integrated over l with the plain sphere measure dl = sinθ' dθ' dψ (no h-Jacobian is
    assumed); D(h) and G1(v) are the BRDF's own, from ``evaluate``.
    """
    ax, ay = alphas
    v = direction_deg(*view_deg)
    brdf = make_brdf(ndf_name, ax, ay)
    l, w = l_sphere_rule(v, max(ax, ay), n_theta=96, n_psi=96)
    out = brdf.evaluate(l, np.broadcast_to(v, l.shape), ("D", "G1_o"))
    total = np.sum(out["D"] * out["G1_o"] / (4.0 * abs(v[2])) * w)
    assert total == pytest.approx(1.0, abs=1e-6)


def test_half_vector_quantities(ndf_name, alphas, rng):
    """evaluate's D and F are taken at h = (l+v)/‖l+v‖ normalised (docs/conventions.md §5):
    D equals ndf.D(h) and Schlick F uses v·h, with h computed here."""
    ax, ay = alphas
    l = random_upper_directions(rng, 2000)
    v = random_upper_directions(rng, 2000)
    h = l + v
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    f0, f90 = 0.04, 0.9
    brdf = make_brdf(ndf_name, ax, ay, fresnel="schlick", f0=f0, f90=f90)
    out = brdf.evaluate(l, v, ("D", "F"))
    # rtol 1e-9: where D ~ e^{−x} (x ≈ 600 in Beckmann-like far tails, D ~ 1e-258) or
    # D ~ cos^{α_p}θ (Blinn-Phong, α_p up to 2e6 at α = 1e-3), a 1-ulp difference between
    # this h and evaluate's h is amplified by x or α_p.
    np.testing.assert_allclose(out["D"], brdf.ndf.D(h), rtol=1e-9, atol=0)
    cos_d = np.clip(np.sum(v * h, axis=-1), 0.0, 1.0)
    np.testing.assert_allclose(out["F"], f0 + (f90 - f0) * (1.0 - cos_d) ** 5, rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("g2", ["separable", "height_correlated"])
@pytest.mark.parametrize("fresnel, params", [("none", {}), ("schlick", {"f0": 0.04, "f90": 1.0}),
                                             ("schlick", {"f0": 0.8, "f90": 0.3})])
@pytest.mark.parametrize("kd", [0.0, 0.4])
def test_reciprocity(ndf_name, alphas, g2, fresnel, params, kd, rng):
    """f(l, v) = f(v, l) (Helmholtz; docs/identities.md §5) at random directions of the
    closed upper hemisphere, 10 % of them exactly grazing (where both graze under the
    height-correlated form both sides are +inf)."""
    ax, ay = alphas
    brdf = make_brdf(ndf_name, ax, ay, g2=g2, fresnel=fresnel, kd=kd, **params)
    l = random_upper_directions(rng, 3000)
    v = random_upper_directions(rng, 3000)
    f_lv, f_vl = brdf.f(l, v), brdf.f(v, l)
    assert not np.any(np.isnan(f_lv))
    np.testing.assert_allclose(f_lv, f_vl, rtol=1e-12, atol=0)


# ---------------------------------------------------------------------- composition

def _D_ref(name, h, ax, ay):
    """Heitz 2014 eq. 83 (Beckmann), 85 (GGX), anisotropic, h in the upper hemisphere."""
    cos2 = h[:, 2] ** 2
    k = (h[:, 0] ** 2 / ax**2 + h[:, 1] ** 2 / ay**2) / cos2      # tan²θ (cos²φ/αx² + sin²φ/αy²)
    if name == "ggx":
        return 1.0 / (np.pi * ax * ay * cos2**2 * (1.0 + k) ** 2)
    return np.exp(-k) / (np.pi * ax * ay * cos2**2)


def _Lambda_ref(name, w, ax, ay):
    """Heitz 2014 eq. 86 (GGX), eq. 84 (Beckmann), with α(φ)² tan²θ = (αx² wx² + αy² wy²)/wz²."""
    from scipy.special import erfc
    a_tan2 = ((ax * w[:, 0]) ** 2 + (ay * w[:, 1]) ** 2) / w[:, 2] ** 2
    if name == "ggx":
        return 0.5 * (np.sqrt(1.0 + a_tan2) - 1.0)
    a = 1.0 / np.sqrt(a_tan2)
    return -0.5 * erfc(a) + np.exp(-a * a) / (2.0 * a * np.sqrt(np.pi))


@pytest.mark.parametrize("name", ["ggx", "beckmann"])
@pytest.mark.parametrize("ax, ay", [(0.1, 0.1), (0.5, 0.5), (1.0, 1.0), (0.2, 0.6)])
@pytest.mark.parametrize("g2", ["separable", "height_correlated"])
def test_f_composition(name, ax, ay, g2, rng):
    """f = kd/π + D(h) F(v·h) G2 / (4 μl μv), everything recomputed here from the
    closed forms (moderate angles, where the plain float formulas are accurate)."""
    n = 2000
    l = random_upper_directions(rng, n, grazing_fraction=0.0)
    v = random_upper_directions(rng, n, grazing_fraction=0.0)
    keep = (l[:, 2] > 0.05) & (v[:, 2] > 0.05)
    l, v = l[keep], v[keep]
    h = (l + v) / np.linalg.norm(l + v, axis=-1, keepdims=True)
    f0, f90, kd = 0.1, 0.95, 0.25
    Ll, Lv = _Lambda_ref(name, l, ax, ay), _Lambda_ref(name, v, ax, ay)
    G2 = 1.0 / ((1 + Ll) * (1 + Lv)) if g2 == "separable" else 1.0 / (1 + Ll + Lv)
    F = f0 + (f90 - f0) * (1.0 - np.sum(v * h, axis=-1)) ** 5
    ref = kd / np.pi + _D_ref(name, h, ax, ay) * F * G2 / (4.0 * l[:, 2] * v[:, 2])
    got = make_brdf(name, ax, ay, g2=g2, fresnel="schlick", kd=kd, f0=f0, f90=f90).f(l, v)
    np.testing.assert_allclose(got, ref, rtol=1e-10)


def test_f_zero_outside_upper_hemisphere(ndf_name, alphas, rng):
    """Reflection only: f = 0 unless both l and v are in the closed upper hemisphere,
    even with kd > 0 (brdf.py contract, docs/conventions.md)."""
    ax, ay = alphas
    brdf = make_brdf(ndf_name, ax, ay, kd=0.5, fresnel="schlick")
    up = random_upper_directions(rng, 500, grazing_fraction=0.0)
    down = up * np.array([1.0, 1.0, -1.0])
    down[:, 2] = np.minimum(down[:, 2], -1e-9)
    down /= np.linalg.norm(down, axis=-1, keepdims=True)
    for l, v in ((down, up), (up, down), (down, down[::-1])):
        assert np.all(brdf.f(l, v) == 0.0)


# -------------------------------------------------------------------------- Fresnel

@pytest.mark.parametrize("f0, f90", [(0.04, 1.0), (0.5, 0.5), (0.9, 0.2), (0.0, 1.0)])
def test_schlick_endpoints(f0, f90):
    """Schlick 1994 eq. 15, F = F0 + (F90 − F0)(1 − cosθ)⁵: F(1) = F0, F(0) = F90,
    monotone in between."""
    fr = FRESNELS["schlick"](f0=f0, f90=f90)
    assert float(fr.F(1.0)) == pytest.approx(f0, abs=1e-15)
    assert float(fr.F(0.0)) == pytest.approx(f90, abs=1e-15)
    c = np.linspace(0.0, 1.0, 101)
    F = fr.F(c)
    np.testing.assert_allclose(F, f0 + (f90 - f0) * (1.0 - c) ** 5, rtol=1e-14, atol=1e-16)
    d = np.diff(F)
    assert np.all(d <= 1e-16) if f90 >= f0 else np.all(d >= -1e-16)


@pytest.mark.parametrize("f0, f90", [(0.04, 1.0), (0.3, 0.7)])
def test_schlick_hemispherical_average(f0, f90):
    """F̄ = 2 ∫_0^1 F(μ) μ dμ = F0 + 2 (F90 − F0)/((p+1)(p+2)), p = 5 (docs/conventions.md §5 on
    seed); for F90 = 1: (20 F0 + 1)/21. Direct quadrature of the code's F."""
    fr = FRESNELS["schlick"](f0=f0, f90=f90)
    x, w = gauss_on(0.0, 1.0, 8)          # exact for the degree-6 polynomial F(μ)μ
    avg = 2.0 * np.sum(w * x * fr.F(x))
    assert avg == pytest.approx(f0 + 2.0 * (f90 - f0) / 42.0, rel=1e-13, abs=0)
    if f90 == 1.0:
        assert avg == pytest.approx((20 * f0 + 1) / 21, rel=1e-13, abs=0)


def test_no_fresnel_is_one():
    fr = FRESNELS["none"]()
    c = np.array([-0.5, 0.0, 1e-300, 0.3, 1.0, 2.0])
    assert np.all(fr.F(c) == 1.0)
    assert fr.F(c).shape == c.shape
