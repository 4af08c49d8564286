"""Fresnel reflectance: exact dielectric and conductor, generalised Schlick, averages.

References: F₀ = ((η−1)/(η+1))²; Born & Wolf sec. 1.5.2 (amplitude ratios r_s, r_p);
Brewster's angle tan θ_B = η where r_p = 0; the normal-incidence reflectance of an
absorbing medium ((η−1)² + κ²)/((η+1)² + κ²); the textbook complex r_s, r_p written out
below in numpy complex and in mpmath; scipy quadrature for the averages.
"""
from __future__ import annotations

import mpmath as mp
import numpy as np
import pytest
from scipy import integrate

from app.physics.fresnel import (FRESNELS, conductor_reflectance, dielectric_reflectance,
                                 f0_from_ior, ior_from_f0)

COS = np.concatenate([[0.0, 1e-300, 1e-12, 1e-6], np.linspace(0.0, 1.0, 201), [1 - 1e-12, 1.0]])
DIELECTRIC_IORS = [1.0, 1.0 + 1e-9, 1.0003, 1.33, 1.5, 2.42, 4.0]
# (η, κ): gold, silver, aluminium, copper at visible wavelengths (Johnson & Christy 1972,
# Rakić 1995: rounded), and the corners of the parameter ranges.
CONDUCTORS = [(0.43, 2.455), (0.05, 3.3), (0.96, 6.69), (0.27, 2.6), (0.01, 0.0), (0.01, 20.0),
              (10.0, 0.0), (10.0, 20.0), (1.0, 1e-6), (1.5, 0.0), (0.5, 0.0), (2.0, 0.1)]


def textbook(cos_i, n):
    """Unpolarised F = (|r_s|² + |r_p|²)/2 with complex n (Born & Wolf):
    r_s = (cos θ_i − n cos θ_t)/(cos θ_i + n cos θ_t), r_p = (n cos θ_i − cos θ_t)/(n cos θ_i
    + cos θ_t), n cos θ_t = √(n² − sin²θ_i) on the branch with non-negative real part."""
    c = np.asarray(cos_i, dtype=complex)
    n = complex(n)
    n_ct = np.sqrt(n * n - (1 - c * c))
    ct = n_ct / n
    rs = (c - n_ct) / (c + n_ct)
    rp = (n * c - ct) / (n * c + ct)
    return 0.5 * (np.abs(rs) ** 2 + np.abs(rp) ** 2)


def textbook_mp(cos_i, eta, k, dps=50, absorptance=False):
    """The same in mpmath at ``dps`` digits (no cancellation issue at all); with
    ``absorptance`` 1 − F, formed before rounding to float."""
    with mp.workdps(dps):
        c = mp.mpf(float(cos_i))
        n = mp.mpc(eta, k)
        n_ct = mp.sqrt(n * n - (1 - c * c))
        if mp.re(n_ct) < 0:
            n_ct = -n_ct
        ct = n_ct / n
        rs = (c - n_ct) / (c + n_ct)
        rp = (n * c - ct) / (n * c + ct)
        F = (abs(rs) ** 2 + abs(rp) ** 2) / 2
        return float(1 - F if absorptance else F)


# ----------------------------------------------------------------------- dielectric

@pytest.mark.parametrize("eta", DIELECTRIC_IORS)
def test_dielectric_normal_incidence_is_2_4(eta):
    F = float(FRESNELS["dielectric"](ior=eta).F(1.0))
    assert F == pytest.approx(((eta - 1) / (eta + 1)) ** 2, rel=1e-13, abs=1e-300)


@pytest.mark.parametrize("eta", [1.0003, 1.33, 1.5, 2.42, 4.0])
def test_dielectric_grazing_is_one_and_brewster_is_closed_form(eta):
    """F(cos 0) = 1 for η > 1; at Brewster's angle (tan θ_B = η) r_p = 0 and
    r_s = (1 − η²)/(1 + η²), so F = ((η² − 1)/(η² + 1))²/2."""
    fr = FRESNELS["dielectric"](ior=eta)
    assert float(fr.F(0.0)) == 1.0
    cos_b = 1 / np.sqrt(1 + eta * eta)
    assert float(fr.F(cos_b)) == pytest.approx(0.5 * ((eta**2 - 1) / (eta**2 + 1)) ** 2, rel=1e-12,
                                              abs=0)


def test_dielectric_without_interface_reflects_nothing():
    """η = 1: no interface, F = 0 at every angle — also at grazing, its limit along cos θ."""
    assert np.all(FRESNELS["dielectric"](ior=1.0).F(COS) == 0.0)


@pytest.mark.parametrize("eta", DIELECTRIC_IORS[1:])
def test_dielectric_against_textbook(eta):
    """Against the complex textbook form at 207 angles (rel 1e-12; the η → 1 cases are
    where the textbook (c − g)/(c + g) cancels, so those use mpmath). η = 1 exactly is
    the previous test (the textbook form is 0/0 at grazing there)."""
    got = dielectric_reflectance(COS, eta)
    if eta - 1 < 1e-3:
        ref = np.array([textbook_mp(c, eta, 0.0) for c in COS])
    else:
        ref = textbook(COS, eta)
    np.testing.assert_allclose(got, ref, rtol=1e-12, atol=1e-300)


# ----------------------------------------------------------------------- conductor

@pytest.mark.parametrize("eta, k", CONDUCTORS)
def test_conductor_against_complex_textbook(eta, k):
    """Real-arithmetic form in fresnel.py against complex arithmetic (numpy), |ΔF| ≤ 1e-13,
    and against mpmath at 50 digits to relative 1e-12 at a few angles (κ ≫ η is where a
    naive a² = (A + t₀)/2 loses digits)."""
    got = conductor_reflectance(COS, eta, k)
    np.testing.assert_allclose(got, textbook(COS, complex(eta, k)), rtol=0, atol=1e-13)
    for c in [0.0, 1e-6, 0.1, 0.5, 0.9, 1.0]:
        assert float(conductor_reflectance(c, eta, k)) == pytest.approx(textbook_mp(c, eta, k),
                                                                         rel=1e-12, abs=1e-300)


@pytest.mark.parametrize("eta, k", [(0.01, 20.0), (0.01, 10.0), (0.02, 15.0)])
def test_conductor_absorptance_when_kappa_dominates(eta, k):
    """κ ≫ η (a near-perfect metal): the absorbed fraction 1 − F ~ 1e-4 keeps 11-12 digits
    against mpmath (5e-12 relative; the 1 − F of the test itself costs ~1e-12). Taking
    a² = (A + t₀)/2 where t₀ ≈ −κ² would lose 2-3 more digits (measured: 2e-11..5e-11)."""
    for c in [1.0, 0.5, 0.1, 0.01]:
        ref = textbook_mp(c, eta, k, dps=60, absorptance=True)
        got = 1.0 - float(conductor_reflectance(c, eta, k))
        assert got == pytest.approx(ref, rel=5e-12, abs=0), c


@pytest.mark.parametrize("eta, k", CONDUCTORS)
def test_conductor_normal_incidence_and_grazing(eta, k):
    """F(1) = ((η−1)² + κ²)/((η+1)² + κ²) (Born & Wolf 14.2), F(0) = 1."""
    fr = FRESNELS["conductor"](ior=eta, k=k)
    ref = ((eta - 1) ** 2 + k * k) / ((eta + 1) ** 2 + k * k)
    assert float(fr.F(1.0)) == pytest.approx(ref, rel=1e-13, abs=0)
    assert float(fr.F(0.0)) == 1.0


def test_conductor_with_no_absorption_is_the_dielectric():
    for eta in [1.0003, 1.33, 1.5, 2.42, 4.0]:
        np.testing.assert_allclose(conductor_reflectance(COS, eta, 0.0), dielectric_reflectance(COS, eta),
                                   rtol=1e-12, atol=1e-15)


def test_conductor_default_is_gold():
    """Johnson & Christy 1972, Au at 548.6 nm: n = 0.43, k = 2.455 → F₀ ≈ 0.787."""
    fr = FRESNELS["conductor"]()
    assert (fr.ior, fr.k) == (0.43, 2.455)
    assert float(fr.F(1.0)) == pytest.approx(0.7869, abs=1e-4)


# ----------------------------------------------------------------------- Schlick

def test_schlick_formula_and_exponent():
    """: F₀ + (F₉₀ − F₀)(1 − cos θ)^p, with p = 5 by default."""
    c = np.linspace(0, 1, 11)
    assert FRESNELS["schlick"]().fresnel_p == 5.0
    for p in [1.0, 2.5, 5.0, 10.0]:
        fr = FRESNELS["schlick"](f0=0.1, f90=0.8, fresnel_p=p)
        np.testing.assert_allclose(fr.F(c), 0.1 + 0.7 * (1 - c) ** p, rtol=1e-14)


@pytest.mark.parametrize("f0", [0.0, 0.02, 0.04, 0.17, 0.5, 0.9, 1.0])
def test_schlick_error_is_zero_at_normal_incidence(f0):
    """The exact counterpart is the dielectric with η from inverted, whose F(1) is f0:
    Schlick's error vanishes at θ = 0 (to rounding of η). At grazing the exact form is 1
    (0 for f0 = 0: η = 1, no interface)."""
    fr = FRESNELS["schlick"](f0=f0)
    exact = fr.exact_counterpart()
    assert exact.name == "dielectric"
    assert float(fr.F(1.0) - exact.F(1.0)) == pytest.approx(0.0, abs=1e-15)
    assert float(exact.F(0.0)) == (1.0 if f0 > 0 else 0.0)


def test_ior_and_f0_round_trip():
    eta = np.array([1.0, 1.33, 1.5, 2.42, 4.0])
    np.testing.assert_allclose(ior_from_f0(f0_from_ior(eta)), eta, rtol=1e-13)
    assert float(ior_from_f0(0.04)) == pytest.approx(1.5, rel=1e-14, abs=0)
    assert float(ior_from_f0(1.0)) == np.inf


@pytest.mark.parametrize("p", [1.0, 2.0, 3.7, 5.0, 10.0])
@pytest.mark.parametrize("f0, f90", [(0.04, 1.0), (0.9, 0.2), (0.0, 0.5)])
def test_schlick_average_against_quadrature(p, f0, f90):
    """F̄ = 2 ∫₀¹ F(μ) μ dμ = F₀ + 2(F₉₀ − F₀)/((p+1)(p+2)) (docs/conventions.md §5)
    against scipy's adaptive quadrature of the definition; for p = 5, F₉₀ = 1 it is
    (20 F₀ + 1)/21. The base class's Gauss rule agrees too."""
    fr = FRESNELS["schlick"](f0=f0, f90=f90, fresnel_p=p)
    ref, err = integrate.quad(lambda mu: 2 * (f0 + (f90 - f0) * (1 - mu) ** p) * mu, 0, 1,
                              epsabs=1e-14, epsrel=1e-14)
    assert fr.F_avg() == pytest.approx(ref, rel=1e-12, abs=1e-15)
    if p == 5.0 and f90 == 1.0:
        assert fr.F_avg() == pytest.approx((20 * f0 + 1) / 21, rel=1e-14, abs=0)
    generic = type(fr).__mro__[1].F_avg(fr)        # Fresnel.F_avg: the Gauss rule
    assert generic == pytest.approx(ref, rel=1e-6)


@pytest.mark.parametrize("name, params", [("dielectric", {"ior": 1.5}), ("dielectric", {"ior": 4.0}),
                                          ("conductor", {}), ("conductor", {"ior": 0.05, "k": 3.3})])
def test_exact_averages_against_quadrature(name, params):
    fr = FRESNELS[name](**params)
    ref, _ = integrate.quad(lambda mu: 2 * float(fr.F(mu)) * mu, 0, 1, epsabs=1e-13, epsrel=1e-13,
                            limit=200)
    assert fr.F_avg() == pytest.approx(ref, rel=1e-9, abs=0)


# ------------------------------------------------------------------ range, finiteness

ALL = [("none", {}), ("schlick", {}), ("schlick", {"f0": 1.0, "f90": 0.0, "fresnel_p": 1.0}),
       ("schlick", {"f0": 0.0, "f90": 1.0, "fresnel_p": 10.0})] + \
      [("dielectric", {"ior": e}) for e in DIELECTRIC_IORS] + \
      [("conductor", {"ior": e, "k": k}) for e, k in CONDUCTORS]


@pytest.mark.parametrize("name, params", ALL)
def test_F_in_unit_interval_and_finite(name, params):
    """F ∈ [0, 1], finite, no floating-point warning (underflow aside) for cos θ in
    [0, 1] and just outside it (rounding of v·h), which is clipped."""
    fr = FRESNELS[name](**params)
    c = np.concatenate([COS, [-1e-16, 1 + 1e-16]])
    with np.errstate(all="raise", under="ignore"):
        F = fr.F(c)
    assert F.shape == c.shape
    assert np.all(np.isfinite(F)) and np.all((F >= 0) & (F <= 1))
    assert F[-2] == F[0] and F[-1] == F[-3]


def test_every_choice_declares_itself():
    for cls in FRESNELS.values():
        assert cls.label and cls.description
        for p in cls.params:
            assert p.contains(p.default)
    assert [p.name for p in FRESNELS["schlick"].params] == ["f0", "f90", "fresnel_p"]
    assert [p.name for p in FRESNELS["conductor"].params] == ["ior", "k"]
