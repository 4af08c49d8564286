"""Directional albedo E(μ) = ∫_{H²} f(l, v)(n·l) dl (docs/conventions.md §3; Kulla & Conty 2017).

References: the brute-force adaptive cubature over l of ``tests/reference.py`` (no slope
space, no change of variables to m) and closed forms derived below.
"""
from __future__ import annotations

import numpy as np
import pytest

from app.integrate.albedo import albedo
from tests.reference import albedo_brute_force

from tests.physics.conftest import make_brdf

MU_GRID = np.array([0.0, 1e-3, 0.02, 0.1, 0.3, 0.5, 0.8, 1.0])


@pytest.mark.parametrize("g2", ["separable", "height_correlated"])
@pytest.mark.parametrize("phi", [0.0, 0.7])
def test_albedo_bounds(ndf_name, alphas, g2, phi):
    """0 ≤ E(μ) ≤ 1 with F = 1, kd = 0 (energy conservation of the single-scattering
    BRDF, docs/identities.md §7): E ≤ 1 + E_error, E ≥ −E_error, and E_error within the
    promised 1e-4."""
    ax, ay = alphas
    res = albedo(make_brdf(ndf_name, ax, ay, g2=g2), MU_GRID, phi)
    assert np.all(np.isfinite(res.E)) and np.all(np.isfinite(res.E_error))
    assert np.all(res.E_error <= 1e-4)
    assert np.all(res.E >= -res.E_error)
    assert np.all(res.E <= 1.0 + res.E_error)


def test_albedo_grazing_height_correlated_is_one(ndf_name, alphas):
    """E(μ = 0) = 1 exactly for the height-correlated form with F = 1.

    Derivation: with dl = 4 (v·m) dm and l = 2(v·m)m − v, at μ_v = 0 every visible facet
    (v·m > 0, m_z > 0) reflects into the upper hemisphere (l_z = 2(v·m) m_z > 0), so
    E = lim ∫_{v·m>0} D(m) (v·m) G2/μ_v dm; G2/G1(v) = (1+Λv)/(1+Λv+Λl) → 1 as Λv → ∞,
    and G1(v) ∫ D (v·m)⁺ dm = μ_v (Smith, Heitz 2014 eq. 13) gives E → 1.
    """
    ax, ay = alphas
    for phi in (0.0, 0.7):
        res = albedo(make_brdf(ndf_name, ax, ay, g2="height_correlated"), [0.0], phi)
        assert abs(res.E[0] - 1.0) <= 1e-4
        assert abs(res.E[0] - 1.0) <= res.E_error[0] + 1e-12


def test_albedo_lambertian_and_constant_fresnel(ndf_name, alphas):
    """∫ (kd/π) μ_l dl = kd exactly, and a constant Fresnel (F0 = F90 = c) scales E by c
    (to within the two reported errors: the adaptive order may stop at a different level
    when the integrand is scaled)."""
    ax, ay = alphas
    mu = np.array([0.05, 0.4, 0.9])
    base = albedo(make_brdf(ndf_name, ax, ay), mu)
    with_kd = albedo(make_brdf(ndf_name, ax, ay, kd=0.3), mu)
    np.testing.assert_allclose(with_kd.E - base.E, 0.3, rtol=0,
                               atol=1e-12 + np.max(with_kd.E_error + base.E_error))
    half = albedo(make_brdf(ndf_name, ax, ay, fresnel="schlick", f0=0.5, f90=0.5), mu)
    assert np.all(np.abs(half.E - 0.5 * base.E) <= half.E_error + 0.5 * base.E_error + 1e-14)


# (ndf, α_x, α_y, g2, μ, φ, reference tolerance). The reference costs ~0.05-1 s each at
# these tolerances; its own error estimate is added to the allowance below. Each
# tolerance was chosen so that tightening it 10× moves the reference by less than its
# error estimate (at 1e-6 the Beckmann α = 0.01 point under-reports its error: 3.2e-9
# off with an estimate of 1.2e-9, hence 1e-7 there).
BRUTE_FORCE_POINTS = [
    ("ggx", 0.01, 0.01, "height_correlated", 0.5, 0.0, 1e-7),         # small α
    ("beckmann", 0.01, 0.01, "height_correlated", 0.5, 0.0, 1e-7),    # small α
    ("ggx", 0.3, 0.3, "height_correlated", 0.02, 0.0, 1e-5),          # grazing
    ("beckmann", 0.3, 0.3, "height_correlated", 0.02, 0.0, 1e-6),     # grazing
    ("ggx", 0.3, 0.3, "separable", 0.0, 0.0, 1e-5),                   # μ = 0
    ("beckmann", 0.1, 0.1, "separable", 0.0, 0.0, 1e-6),              # μ = 0
    ("beckmann", 0.05, 0.5, "height_correlated", 0.4, 0.7, 1e-6),     # aniso, φ
    ("ggx", 1.0, 0.1, "height_correlated", 0.1, 2.0, 1e-6),           # aniso, φ
    ("ggx", 0.05, 0.5, "height_correlated", 0.02, 0.7, 1e-6),         # aniso, grazing
]


@pytest.mark.parametrize("name, ax, ay, g2, mu, phi, tol", BRUTE_FORCE_POINTS,
                         ids=[f"{p[0]}-{p[1]:g}-{p[2]:g}-{p[3][:3]}-mu{p[4]:g}-phi{p[5]:g}"
                              for p in BRUTE_FORCE_POINTS])
def test_albedo_against_brute_force(name, ax, ay, g2, mu, phi, tol):
    """E from app.integrate.albedo against tests/reference.albedo_brute_force (adaptive
    cubature of f(l,v)μ_l over (μ_l, φ_l)): within 1e-4 and within the reported
    E_error plus the reference's own error estimate."""
    brdf = make_brdf(name, ax, ay, g2=g2)
    res = albedo(brdf, [mu], phi)
    ref, ref_err, _ = albedo_brute_force(brdf, mu, phi, tol=tol)
    diff = abs(res.E[0] - ref)
    assert diff <= 1e-4
    assert diff <= res.E_error[0] + ref_err + 1e-12
