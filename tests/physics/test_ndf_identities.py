"""Identities of the normal distribution D (docs/identities.md §1, §2) and its closed forms.

References: Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based
BRDFs", JCGT 3(2): eq. 4 (normalisation), eq. 5 (projected area), eq. 83 (anisotropic
Beckmann), eq. 85 (anisotropic GGX); Walter et al. 2007 eq. 25, 33 (isotropic forms).
"""
from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from app.physics.vectors import direction_deg

from .conftest import make_ndf, m_hemisphere_rule

# Views for the projected-area identity: normal, oblique, grazing and exactly horizontal.
VIEWS_DEG = [(0.0, 0.0), (30.0, 20.0), (60.0, 135.0), (85.0, 250.0), (89.9, 300.0), (90.0, 45.0)]


def test_normalisation(ndf_name, alphas):
    """∫_{H²} D(m)(n·m) dm = 1 (Heitz 2014 eq. 4; docs/identities.md §1)."""
    ax, ay = alphas
    ndf = make_ndf(ndf_name, ax, ay)
    m, w = m_hemisphere_rule(ax, ay, n_beta=64, n_phi=64)
    total = np.sum(ndf.D(m) * m[:, 2] * w)
    assert total == pytest.approx(1.0, rel=1e-10, abs=0)


@pytest.mark.parametrize("view_deg", VIEWS_DEG, ids=lambda t: f"v{t[0]:g}-{t[1]:g}")
def test_signed_projected_area(ndf_name, alphas, view_deg):
    """∫_{S²} D(m)(v·m) dm = n·v over the full sphere of m (signed, Heitz 2014 eq. 5;
    docs/identities.md §2). D = 0 below the horizon, so the integral is over H² with the
    sign of v·m kept."""
    ax, ay = alphas
    v = direction_deg(*view_deg)
    ndf = make_ndf(ndf_name, ax, ay)
    m, w = m_hemisphere_rule(ax, ay, n_beta=64, n_phi=64, v=v)
    total = np.sum(ndf.D(m) * (m @ v) * w)
    assert total == pytest.approx(v[2], rel=1e-9, abs=1e-11)


@pytest.mark.parametrize("r_stretched", [0.1, 1.0, 3.0, 30.0])
def test_radial_cdf_is_mass_of_D(ndf_name, alphas, r_stretched):
    """radial_cdf(r̃²) = ∫ D(m)(n·m) dm over the normals whose stretched slope
    r̃(m) = √((m_x/α_x)² + (m_y/α_y)²)/m_z is ≤ r̃ (base.py contract; the albedo
    integrator and D·cos sampling rely on it instead of D), and radial_cdf_inv inverts it."""
    ax, ay = alphas
    ndf = make_ndf(ndf_name, ax, ay)
    # every NDF gives its radial CDF (the albedo quadrature and the samplers need it)
    assert hasattr(ndf, "radial_cdf") and hasattr(ndf, "radial_ccdf_inv")
    m, w = m_hemisphere_rule(ax, ay, n_beta=48, n_phi=48, beta_max=np.arctan(r_stretched))
    mass = np.sum(ndf.D(m) * m[:, 2] * w)
    r2 = np.float64(r_stretched**2)
    assert float(ndf.radial_cdf(r2)) == pytest.approx(mass, rel=1e-10, abs=0)
    c = ndf.radial_cdf(r2)
    if 1.0 - c > 1e-8:   # beyond, C rounds to 1 and the inverse is ill-conditioned (→ ∞)
        assert float(ndf.radial_cdf_inv(c)) == pytest.approx(r_stretched**2, rel=1e-6, abs=0)


def test_D_vanishes_below_horizon(ndf_name, alphas):
    """D = 0 for n·m < 0 (docs/conventions.md)."""
    ax, ay = alphas
    ndf = make_ndf(ndf_name, ax, ay)
    th = np.array([90.0 + 1e-9, 91.0, 120.0, 179.0, 180.0])
    m = direction_deg(th[:, None], np.array([0.0, 33.0, 90.0, 200.0])[None, :]).reshape(-1, 3)
    assert np.all(ndf.D(m) == 0.0)


# ----------------------------------------------------------------------- closed forms

def _mp_angles(m):
    """tan²θ, cos²φ, sin²φ, cos²θ of a float direction, exactly, in mpmath."""
    mx, my, mz = (mp.mpf(float(c)) for c in m)
    r2 = mx * mx + my * my
    tan2 = r2 / (mz * mz)
    c2 = mx * mx / r2 if r2 > 0 else mp.mpf(1)
    return tan2, c2, 1 - c2, mz * mz / (r2 + mz * mz)


def ggx_D_ref(m, ax, ay):
    """Heitz 2014 eq. 85 (Walter 2007 eq. 33 when α_x = α_y):
    D = 1 / (π α_x α_y cos⁴θ (1 + tan²θ (cos²φ/α_x² + sin²φ/α_y²))²)."""
    with mp.workdps(40):
        tan2, c2, s2, cos2 = _mp_angles(m)
        ax, ay = mp.mpf(ax), mp.mpf(ay)
        return float(1 / (mp.pi * ax * ay * cos2 ** 2 * (1 + tan2 * (c2 / ax**2 + s2 / ay**2)) ** 2))


def beckmann_D_ref(m, ax, ay):
    """Heitz 2014 eq. 83 (Walter 2007 eq. 25 when α_x = α_y):
    D = exp(−tan²θ (cos²φ/α_x² + sin²φ/α_y²)) / (π α_x α_y cos⁴θ)."""
    with mp.workdps(40):
        tan2, c2, s2, cos2 = _mp_angles(m)
        ax, ay = mp.mpf(ax), mp.mpf(ay)
        return float(mp.exp(-tan2 * (c2 / ax**2 + s2 / ay**2)) / (mp.pi * ax * ay * cos2 ** 2))


D_REFERENCES = {"ggx": ggx_D_ref, "beckmann": beckmann_D_ref}
SAMPLE_M_DEG = [(0.0, 0.0), (1e-3, 10.0), (5.0, 30.0), (20.0, 75.0), (45.0, 135.0), (70.0, 200.0),
                (85.0, 290.0)]


@pytest.mark.parametrize("name", sorted(D_REFERENCES))
@pytest.mark.parametrize("ax, ay", [(1e-3, 1e-3), (0.05, 0.05), (0.3, 0.3), (1.0, 1.0),
                                    (0.05, 0.5), (1.0, 0.1)])
def test_D_closed_form(name, ax, ay):
    """D at sample directions against the formula written out (mpmath, 40 digits)."""
    ndf = make_ndf(name, ax, ay)
    for th, ph in SAMPLE_M_DEG:
        m = direction_deg(th, ph)
        ref = D_REFERENCES[name](m, ax, ay)
        got = float(ndf.D(m))
        if ref < 1e-300:   # the reference underflows double precision: D must be ~0
            assert got < 1e-290
        else:
            assert got == pytest.approx(ref, rel=1e-12, abs=0), (th, ph)


@pytest.mark.parametrize("name", sorted(D_REFERENCES))
def test_D_peak_value(name, alphas):
    """D(n) = 1/(π α_x α_y) for both (eq. 83, 85 at θ = 0)."""
    ax, ay = alphas
    assert float(make_ndf(name, ax, ay).D(np.array([0.0, 0.0, 1.0]))) == pytest.approx(
        1.0 / (np.pi * ax * ay), rel=1e-14, abs=0)
