"""Smith masking: Λ, G1 and G2 against the general Smith integral, closed forms and bounds.

References: Heitz 2014, JCGT 3(2): eq. 13 (general Smith G1),
eq. 43 (G1 = 1/(1+Λ)), eq. 84 (Beckmann Λ), eq. 86 (GGX Λ), eq. 98 (separable G2),
eq. 99 (height-correlated G2); Walter et al. 2007 eq. 27, 34.
"""
from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest

from app.physics.g2 import G2_FORMS, azimuth_difference
from app.physics.masking import G1, MASKINGS
from app.physics.vectors import direction_deg

from .conftest import exact_smith, make_ndf, m_hemisphere_rule, make_brdf, random_upper_directions

SMITH = MASKINGS["smith"]
VIEWS_DEG = [(0.0, 0.0), (30.0, 20.0), (60.0, 135.0), (85.0, 250.0), (89.9, 300.0)]


@pytest.mark.parametrize("view_deg", VIEWS_DEG, ids=lambda t: f"v{t[0]:g}-{t[1]:g}")
def test_smith_integral(ndf_name, alphas, view_deg):
    """∫ G1(v, m) D(m) (v·m)⁺ dm = n·v with G1(v, m) = χ⁺(v·m) G1(v) and G1(v) from the
    analytic Λ (docs/identities.md §3): the closed-form Λ agrees with the general Smith
    G1 = n·v / ∫ D(m)(v·m)⁺ dm (Heitz 2014 eq. 13)."""
    ax, ay = alphas
    v = direction_deg(*view_deg)
    ndf = make_ndf(ndf_name, ax, ay)
    m, w = m_hemisphere_rule(ax, ay, n_beta=64, n_phi=64, v=v)
    projected = np.sum(ndf.D(m) * np.maximum(m @ v, 0.0) * w)
    g1 = float(G1(v[2], exact_smith(ndf_name).mu_Lambda(ndf, v)))
    assert g1 * projected == pytest.approx(v[2], rel=1e-7, abs=0)


# ----------------------------------------------------------------------- closed forms

def _mp_dir(w, ax, ay):
    """μ, tanθ and α(φ) = √(cos²φ α_x² + sin²φ α_y²) (Heitz 2014 sec. 5.3) in mpmath,
    exactly from the float components of w."""
    wx, wy, wz = (mp.mpf(float(c)) for c in w)
    s = mp.sqrt((ax * wx) ** 2 + (ay * wy) ** 2)          # α(φ) sinθ
    r = mp.sqrt(wx * wx + wy * wy)
    return wz, r / wz, s / r


def ggx_Lambda_ref(w, ax, ay):
    """Λ = (−1 + √(1 + α(φ)² tan²θ))/2 (Heitz 2014 eq. 86; Walter 2007 eq. 34 with a)."""
    with mp.workdps(40):
        _, tan_t, a_phi = _mp_dir(w, mp.mpf(ax), mp.mpf(ay))
        return (-1 + mp.sqrt(1 + a_phi ** 2 * tan_t ** 2)) / 2


def beckmann_Lambda_ref(w, ax, ay):
    """Λ(a) = (erf a − 1)/2 + e^{−a²}/(2a√π), a = 1/(α(φ) tanθ) (Heitz 2014 eq. 84,
    Walter 2007 eq. 27); erf a − 1 taken as −erfc a, 60 digits for the cancellation."""
    with mp.workdps(60):
        _, tan_t, a_phi = _mp_dir(w, mp.mpf(ax), mp.mpf(ay))
        a = 1 / (a_phi * tan_t)
        return -mp.erfc(a) / 2 + mp.exp(-a * a) / (2 * a * mp.sqrt(mp.pi))


LAMBDA_REFERENCES = {"ggx": ggx_Lambda_ref, "beckmann": beckmann_Lambda_ref}
# μΛ at μ = 0: lim μΛ = α(φ)/2 (GGX), α(φ)/(2√π) (Beckmann) — the leading terms of
# eq. 86 (Λ ~ α tanθ/2) and eq. 84 (Λ ~ 1/(2a√π)) as tanθ → ∞.
MU_LAMBDA_AT_GRAZING = {"ggx": lambda a: a / 2.0, "beckmann": lambda a: a / (2.0 * np.sqrt(np.pi))}
SAMPLE_DEG = [(1e-3, 0.0), (10.0, 30.0), (30.0, 90.0), (45.0, 120.0), (60.0, 200.0), (80.0, 260.0),
              (89.0, 330.0), (89.99, 10.0)]


@pytest.mark.parametrize("name", sorted(LAMBDA_REFERENCES))
@pytest.mark.parametrize("ax, ay", [(1e-3, 1e-3), (0.05, 0.05), (0.3, 0.3), (1.0, 1.0),
                                    (0.05, 0.5), (1.0, 0.1)])
def test_Lambda_closed_form(name, ax, ay):
    """Λ at sample directions (iso and aniso via α(φ)) against the written-out formula."""
    ndf = make_ndf(name, ax, ay)
    for th, ph in SAMPLE_DEG:
        w = direction_deg(th, ph)
        ref = LAMBDA_REFERENCES[name](w, ax, ay)
        got = float(ndf.Lambda(w))
        if ref < mp.mpf("1e-300"):
            assert got < 1e-290, (th, ph)
        else:
            assert got == pytest.approx(float(ref), rel=1e-12, abs=0), (th, ph)


@pytest.mark.parametrize("a", [0.05, 0.5, 1.0, 1.6, 3.0, 6.0, 8.0, 10.0, 20.0])
@pytest.mark.parametrize("ax, ay, phi_deg", [(0.5, 0.5, 0.0), (0.2, 0.7, 30.0)])
def test_beckmann_Lambda_large_a(a, ax, ay, phi_deg):
    """Beckmann Λ(a) against mpmath to relative 1e-12, also where the code switches to an
    asymptotic series (a ≥ 6). tanθ = 1/(α(φ) a) puts the direction at the wanted a;
    the reference uses the exact float components, so the rounding of θ does not count."""
    phi = np.deg2rad(phi_deg)
    a_phi = np.sqrt(np.cos(phi) ** 2 * ax ** 2 + np.sin(phi) ** 2 * ay ** 2)
    theta = np.arctan(1.0 / (a_phi * a))
    w = np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])
    ref = beckmann_Lambda_ref(w, ax, ay)
    got = float(make_ndf("beckmann", ax, ay).Lambda(w))
    assert got == pytest.approx(float(ref), rel=1e-12, abs=0)


@pytest.mark.parametrize("name", sorted(MU_LAMBDA_AT_GRAZING))
@pytest.mark.parametrize("ax, ay", [(1e-4, 1e-4), (0.3, 0.3), (1.0, 1.0), (0.05, 0.5)])
@pytest.mark.parametrize("phi_deg", [0.0, 30.0, 90.0, 225.0])
def test_G1_limits(name, ax, ay, phi_deg):
    """G1 = 1 at θ = 0, G1 = 0 at θ = 90°, Λ(90°) = +inf, and μΛ → α(φ)/2 (GGX),
    α(φ)/(2√π) (Beckmann) as μ → 0 (at μ = 0 exactly and at μ = 1e-12)."""
    ndf = make_ndf(name, ax, ay)
    phi = np.deg2rad(phi_deg)
    a_phi = np.sqrt(np.cos(phi) ** 2 * ax ** 2 + np.sin(phi) ** 2 * ay ** 2)
    up = direction_deg(0.0, phi_deg)
    flat = direction_deg(90.0, phi_deg)
    assert flat[2] == 0.0
    assert float(G1(up[2], SMITH.mu_Lambda(ndf, up))) == 1.0
    assert float(G1(flat[2], SMITH.mu_Lambda(ndf, flat))) == 0.0
    assert float(ndf.Lambda(flat)) == np.inf
    expected = MU_LAMBDA_AT_GRAZING[name](a_phi)
    assert float(ndf.mu_Lambda(flat)) == pytest.approx(expected, rel=1e-13, abs=0)
    # Next term of both expansions: μΛ(μ) = μΛ(0) − μ/2 + O(μ²/α(φ)) (GGX: (√(μ²+s²) − μ)/2;
    # Beckmann: Λ(a) = −1/2 + 1/(2a√π) + a/(2√π) + O(a³)).
    mu = 1e-12
    near = np.array([np.sqrt(1 - mu * mu) * np.cos(phi), np.sqrt(1 - mu * mu) * np.sin(phi), mu])
    assert float(ndf.mu_Lambda(near)) == pytest.approx(expected - mu / 2, rel=1e-12, abs=0)


# ----------------------------------------------------------------------------- G2

def test_G2_bounds(ndf_name, alphas, rng):
    """0 ≤ G2 ≤ min(G1(l), G1(v)); separable ≤ height-correlated (docs/identities.md §6).
    (1+Λl)(1+Λv) = 1 + Λl + Λv + ΛlΛv ≥ 1 + Λl + Λv gives the second (Heitz 2014 sec. 6)."""
    ax, ay = alphas
    n = 4000
    l = random_upper_directions(rng, n)
    v = random_upper_directions(rng, n)
    want = ("G2", "G1_i", "G1_o")
    sep = make_brdf(ndf_name, ax, ay, g2="separable").evaluate(l, v, want)
    hc = make_brdf(ndf_name, ax, ay, g2="height_correlated").evaluate(l, v, want)
    eps = 4 * np.finfo(float).eps
    for out in (sep, hc):
        assert np.all(np.isfinite(out["G2"]))
        assert np.all(out["G2"] >= 0.0)
        assert np.all(out["G2"] <= np.minimum(out["G1_i"], out["G1_o"]) * (1 + eps))
    assert np.all(sep["G2"] <= hc["G2"] * (1 + eps))


def _ref_G2(name, l, v, ax, ay):
    """Separable G1(l)G1(v) (eq. 98) and height-correlated 1/(1+Λl+Λv) (eq. 99),
    from the mpmath Λ of this file."""
    ref = LAMBDA_REFERENCES[name]
    Ll, Lv = ref(l, ax, ay), ref(v, ax, ay)
    return float(1 / ((1 + Ll) * (1 + Lv))), float(1 / (1 + Ll + Lv))


@pytest.mark.parametrize("name", sorted(LAMBDA_REFERENCES))
@pytest.mark.parametrize("ax, ay", [(0.01, 0.01), (0.3, 0.3), (1.0, 1.0), (0.05, 0.5), (1.0, 0.1)])
def test_G2_closed_forms(name, ax, ay):
    pairs = [((10.0, 0.0), (20.0, 180.0)), ((45.0, 30.0), (60.0, 100.0)),
             ((80.0, 0.0), (85.0, 270.0)), ((89.0, 45.0), (5.0, 45.0)), ((70.0, 10.0), (70.0, 10.0))]
    for (tl, pl), (tv, pv) in pairs:
        l, v = direction_deg(tl, pl), direction_deg(tv, pv)
        sep_ref, hc_ref = _ref_G2(name, l, v, ax, ay)
        sep = make_brdf(name, ax, ay, g2="separable").evaluate(l, v, ("G2",))["G2"]
        hc = make_brdf(name, ax, ay, g2="height_correlated").evaluate(l, v, ("G2",))["G2"]
        assert float(sep) == pytest.approx(sep_ref, rel=1e-12, abs=0)
        assert float(hc) == pytest.approx(hc_ref, rel=1e-12, abs=0)


@pytest.mark.parametrize("alpha", [1e-3, 0.1, 0.5, 1.0])
def test_ggx_height_correlated_visibility(alpha, rng):
    """Isotropic GGX: V = G2/(4 μl μv) = 0.5 / (μl √(μv²(1−α²) + α²) + μv √(μl²(1−α²) + α²))
    exactly (Heitz 2014 eq. 99 with eq. 86) — an identity, not an approximation."""
    n = 500
    mu_l, mu_v = rng.uniform(1e-3, 1.0, n), rng.uniform(1e-3, 1.0, n)
    ndf = make_ndf("ggx", alpha)
    l = np.stack([np.sqrt(1 - mu_l**2), np.zeros(n), mu_l], -1)
    v = np.stack([np.zeros(n), np.sqrt(1 - mu_v**2), mu_v], -1)
    _, V = G2_FORMS["height_correlated"].G2_and_V(mu_l, mu_v, SMITH.mu_Lambda(ndf, l),
                                                  SMITH.mu_Lambda(ndf, v))
    a2 = alpha * alpha
    ref = 0.5 / (mu_l * np.sqrt(mu_v**2 * (1 - a2) + a2) + mu_v * np.sqrt(mu_l**2 * (1 - a2) + a2))
    np.testing.assert_allclose(V, ref, rtol=1e-12)


def test_G2_forms_return_V(ndf_name, alphas, rng):
    """Each G2 form's V equals G2/(4 μl μv) wherever μl μv > 0 (g2.py contract), for
    every form that applies to this NDF and α (hammon: isotropic GGX only)."""
    ax, ay = alphas
    ndf = make_ndf(ndf_name, ax, ay)
    l = random_upper_directions(rng, 1000, grazing_fraction=0.0)
    v = random_upper_directions(rng, 1000, grazing_fraction=0.0)
    ok = (l[:, 2] > 1e-6) & (v[:, 2] > 1e-6)
    l, v = l[ok], v[ok]
    phi = azimuth_difference(l, v)
    for form in G2_FORMS.values():
        if (form.applies_to and ndf_name not in form.applies_to) or \
                (form.isotropic_only and not ndf.isotropic):
            continue
        G2, V = form.G2_and_V(l[:, 2], v[:, 2], SMITH.mu_Lambda(ndf, l), SMITH.mu_Lambda(ndf, v),
                              phi=phi, ndf=ndf, lambda_phi=None)
        np.testing.assert_allclose(V, G2 / (4 * l[:, 2] * v[:, 2]), rtol=1e-12)
