"""Fresnel reflectance F(cos θ_d), θ_d the angle between l (or v) and h (MATH.md errata).

Light arrives from outside (a medium of index 1, air) onto the surface:

* ``none``        F = 1
* ``schlick``     F = F₀ + (F₉₀ − F₀)(1 − cos θ)^p                      (2-3), p = 5: Schlick
* ``dielectric``  exact, unpolarised, real index η = n₂/n₁ ≥ 1           F₀ = ((η−1)/(η+1))² (2-4)
* ``conductor``   exact, unpolarised, complex index η + iκ

Every F is in [0, 1] and finite for cos θ ∈ [0, 1]; F(0) = 1 for every exact form with an
interface (η ≠ 1 or κ > 0).

References
----------
Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", eq. 15;
seed 000 (2-3), (2-4), (3-58) (see MATH.md errata for its exponent convention);
Born & Wolf, "Principles of Optics", sec. 1.5.2 (dielectric) and 14.2 (absorbing media);
Pharr, Jakob, Humphreys, pbrt-v4 (2023), sec. 9.3 "FrDielectric" and 9.3.6 "FrComplex".
"""
from __future__ import annotations

from typing import ClassVar

import numpy as np

from .numeric import where_valid
from .params import Param

F0 = Param("f0", "F₀ (reflectance at 0°)", 0.0, 1.0, 0.04,
           "Reflectance at normal incidence (0.04 is a typical dielectric).")
F90 = Param("f90", "F₉₀ (reflectance at 90°)", 0.0, 1.0, 1.0,
            "Reflectance at grazing incidence.")
FRESNEL_P = Param("fresnel_p", "p (Schlick exponent)", 1.0, 10.0, 5.0,
                  "Exponent p of (1 − cos θ)^p in the generalised Schlick form (2-3); 5 is Schlick's.")
IOR_DIELECTRIC = Param("ior", "η (index of refraction)", 1.0, 4.0, 1.5,
                       "Relative index η = n₂/n₁ of the surface seen from air; 1.5 is glass "
                       "(F₀ = 0.04), 1.33 water, 2.42 diamond.")
# Gold at λ = 548.6 nm: n = 0.43, k = 2.455 (Johnson & Christy 1972, Phys. Rev. B 6, 4370,
# table I); F₀ = ((n−1)² + k²)/((n+1)² + k²) ≈ 0.787.
IOR_CONDUCTOR = Param("ior", "η (real part of the index)", 0.01, 10.0, 0.43,
                      "Real part η of the complex index η + iκ; default: gold at 548.6 nm "
                      "(Johnson & Christy 1972).")
K_CONDUCTOR = Param("k", "κ (extinction coefficient)", 0.0, 20.0, 2.455,
                    "Imaginary part κ of the complex index η + iκ; default: gold at 548.6 nm "
                    "(Johnson & Christy 1972).")


def _cos(cos_theta) -> np.ndarray:
    """cos θ as float, clipped to [0, 1] (rounding of v·h may leave it just outside)."""
    return np.clip(np.asarray(cos_theta, dtype=float), 0.0, 1.0)


def f0_from_ior(eta):
    """F₀ = ((η − 1)/(η + 1))² (2-4)."""
    eta = np.asarray(eta, dtype=float)
    return ((eta - 1.0) / (eta + 1.0)) ** 2


def ior_from_f0(f0):
    """η ≥ 1 with ((η − 1)/(η + 1))² = F₀, F₀ ∈ [0, 1): η = (1 + √F₀)/(1 − √F₀) ((2-4)
    inverted); +inf at F₀ = 1."""
    r = np.sqrt(np.asarray(f0, dtype=float))
    return where_valid(r < 1.0, [r], lambda x: (1.0 + x) / (1.0 - x), np.inf)


def dielectric_reflectance(cos_theta, eta):
    """Exact unpolarised Fresnel reflectance F = (r_s² + r_p²)/2 for light from index 1
    onto index η ≥ 1 (Born & Wolf sec. 1.5.2; pbrt-v4 FrDielectric).

    With c = cos θ, d = η² − 1 = (η − 1)(η + 1) and g = η cos θ_t = √(d + c²) (Snell:
    η² sin²θ_t = sin²θ), the amplitude ratios r_s = (c − g)/(c + g) and
    r_p = (η² c − g)/(η² c + g) are written with numerator and denominator multiplied by
    the denominator, and the squares expanded with g² = d + c²:

        r_s = −d / (d + 2c(c + g)),
        r_p = d((η² + 1)c² − 1) / (d + c² + η²c(η²c + 2g)).

    Nothing cancels when η → 1 (d is formed from η − 1), every denominator term is ≥ 0,
    and at c = 0 both are −d/d = −1 exactly, so F(0) = 1 exactly. A denominator is 0
    only when d = 0 and c = 0 (or they underflow): no interface, F = 0 (its limit along
    c). η = +inf (a perfect mirror, F₀ = 1) gives F = 1.
    """
    c = _cos(cos_theta)
    eta = np.asarray(eta, dtype=float)
    c, eta = np.broadcast_arrays(c, eta)
    return where_valid(np.isfinite(eta), [c, eta], _dielectric_finite, 1.0)


def _dielectric_finite(c, eta):
    e2 = eta * eta
    d = (eta - 1.0) * (eta + 1.0)
    g = np.sqrt(d + c * c)
    den_s = d + 2.0 * c * (c + g)
    den_p = d + c * c + e2 * c * (e2 * c + 2.0 * g)
    ok = (den_s > 0) & (den_p > 0)

    def F(c, e2, d, den_s, den_p):
        rs = -d / den_s
        rp = d * ((e2 + 1.0) * c * c - 1.0) / den_p
        return 0.5 * (rs * rs + rp * rp)

    return where_valid(ok, [c, e2, d, den_s, den_p], F, 0.0)


def conductor_reflectance(cos_theta, eta, k):
    """Exact unpolarised Fresnel reflectance of an absorbing medium of complex index
    η + iκ seen from index 1, in real arithmetic (Born & Wolf sec. 14.2; the same
    quantity as pbrt-v4's FrComplex, which uses complex numbers).

    With s² = sin²θ, c = cos θ, t₀ = η² − κ² − s² and A = a² + b² = √(t₀² + 4η²κ²),
    where a + ib = √((η + iκ)² − s²) (the complex η cos θ_t):

        a² = (A + t₀)/2,    R_s = ((a − c)² + b²)/((a + c)² + b²),
        R_p = R_s (A c² + s⁴ − 2 a c s²)/(A c² + s⁴ + 2 a c s²),    F = (R_s + R_p)/2.

    a² is taken as 2η²κ²/(A − t₀) when t₀ < 0, where A + t₀ would cancel (κ ≫ η, as for
    silver or aluminium); b² = A − a² likewise as 2η²κ²/(A + t₀) when t₀ ≥ 0. Those
    denominators vanish only for η = κ = 0, which the parameter ranges exclude (η ≥ 0.01);
    there the product ηκ = 0 and a² (or b²) is 0. At c = 0: R_s = R_p = 1.
    """
    c = _cos(cos_theta)
    eta = np.asarray(eta, dtype=float)
    k = np.asarray(k, dtype=float)
    c2 = c * c
    s2 = np.maximum(1.0 - c2, 0.0)
    t0 = eta * eta - k * k - s2
    A = np.sqrt(t0 * t0 + 4.0 * (eta * k) ** 2)
    # (A + t₀)(A − t₀) = 4η²κ²: use whichever factor does not cancel.
    pos = t0 >= 0
    a2 = np.where(pos, 0.5 * (A + np.abs(t0)),
                  where_valid(A - t0 > 0, [eta * k, A - t0], lambda ek, d: 2.0 * ek * ek / d, 0.0))
    b2 = np.where(pos, where_valid(A + t0 > 0, [eta * k, A + t0], lambda ek, d: 2.0 * ek * ek / d, 0.0),
                  0.5 * (A - t0))
    a = np.sqrt(a2)
    Rs = ((a - c) ** 2 + b2) / ((a + c) ** 2 + b2)
    u = A * c2 + s2 * s2
    v = 2.0 * a * c * s2
    Rp = Rs * (u - v) / (u + v)
    return 0.5 * (Rs + Rp)


# ------------------------------------------------------------------------- registry

class Fresnel:
    name: ClassVar[str]
    label: ClassVar[str]
    description: ClassVar[str]
    reference: ClassVar[str] = ""
    params: ClassVar[tuple[Param, ...]] = ()

    def __init__(self, **values: float):
        for p in self.params:
            setattr(self, p.name, float(values.get(p.name, p.default)))

    def F(self, cos_theta_d) -> np.ndarray:
        raise NotImplementedError

    def F_avg(self) -> float:
        """Cosine-weighted hemispherical average F̄ = 2 ∫₀¹ F(μ) μ dμ (Kulla-Conty 2017),
        by a 64-point Gauss-Legendre rule in μ (F is smooth in μ for the exact forms);
        a closed form overrides this where one exists."""
        x, w = np.polynomial.legendre.leggauss(64)
        mu, w = 0.5 * (x + 1.0), 0.5 * w
        return float(2.0 * np.sum(self.F(mu) * mu * w))

    def exact_counterpart(self) -> "Fresnel | None":
        """The exact form this one approximates (for error plots), or None."""
        return None


class NoFresnel(Fresnel):
    name = "none"
    label = "None (F = 1)"
    description = "F = 1: shows D and G alone; with it the white-furnace tests apply."

    def F(self, cos_theta_d):
        return np.ones_like(np.asarray(cos_theta_d, dtype=float))

    def F_avg(self):
        return 1.0


class Schlick(Fresnel):
    name = "schlick"
    label = "Schlick"
    description = ("F = F₀ + (F₉₀ − F₀)(1 − cos θ_d)^p: Schlick 1994 with p = 5, F₉₀ = 1; "
                   "its error is shown against the exact dielectric of the same F₀.")
    reference = "Schlick 1994, eq. 15; seed 000 (2-3)"
    params = (F0, F90, FRESNEL_P)

    def F(self, cos_theta_d):
        return self.f0 + (self.f90 - self.f0) * (1.0 - _cos(cos_theta_d)) ** self.fresnel_p

    def F_avg(self):
        """2 ∫₀¹ (F₀ + (F₉₀ − F₀)(1 − μ)^p) μ dμ = F₀ + 2(F₉₀ − F₀)/((p + 1)(p + 2)), since
        2 ∫₀¹ (1 − μ)^p μ dμ = 2 B(2, p + 1). (MATH.md errata: (3-58) of seed 000 is this
        for the exponent 1/p; for p = 5, F₉₀ = 1 it is (20 F₀ + 1)/21.)"""
        p = self.fresnel_p
        return self.f0 + 2.0 * (self.f90 - self.f0) / ((p + 1.0) * (p + 2.0))

    def exact_counterpart(self):
        """The exact dielectric with the same F₀: η = (1 + √F₀)/(1 − √F₀) ((2-4) inverted;
        F₀ = 1 is the limit η → ∞, a perfect mirror)."""
        return Dielectric(ior=float(ior_from_f0(self.f0)))


class Dielectric(Fresnel):
    name = "dielectric"
    label = "Dielectric (exact)"
    description = "Exact unpolarised Fresnel reflectance of a dielectric of index η seen from air."
    reference = "Born & Wolf, Principles of Optics, sec. 1.5.2; F₀ from (2-4)"
    params = (IOR_DIELECTRIC,)

    def F(self, cos_theta_d):
        return dielectric_reflectance(cos_theta_d, self.ior)


class Conductor(Fresnel):
    name = "conductor"
    label = "Conductor (exact)"
    description = ("Exact unpolarised Fresnel reflectance of a metal of complex index η + iκ "
                   "seen from air (one wavelength).")
    reference = "Born & Wolf, Principles of Optics, sec. 14.2; pbrt-v4 FrComplex"
    params = (IOR_CONDUCTOR, K_CONDUCTOR)

    def F(self, cos_theta_d):
        return conductor_reflectance(cos_theta_d, self.ior, self.k)


FRESNELS: dict[str, type[Fresnel]] = {
    cls.name: cls for cls in (NoFresnel, Schlick, Dielectric, Conductor)}
