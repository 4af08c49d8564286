"""Exact unpolarised Fresnel reflectance of a dielectric of real index η seen from air.

References
----------
Born & Wolf, "Principles of Optics", sec. 1.5.2; Pharr, Jakob, Humphreys, pbrt-v4
(2023), sec. 9.3 "FrDielectric".
"""
from __future__ import annotations

import math

import numpy as np

from ..numeric import where_valid
from ..params import Param
from ..formula import Formula
from .base import FRESNELS, Fresnel, _cos, clip_cos_scalar

IOR_DIELECTRIC = Param("ior", "η (index of refraction)", 1.0, 4.0, 1.5,
                       "Relative index η = n₂/n₁ of the surface seen from air; 1.5 is glass "
                       "(F₀ = 0.04), 1.33 water, 2.42 diamond.")


def f0_from_ior(eta):
    """F₀ = ((η − 1)/(η + 1))² (normal incidence)."""
    eta = np.asarray(eta, dtype=float)
    return ((eta - 1.0) / (eta + 1.0)) ** 2


def ior_from_f0(f0):
    """η ≥ 1 with ((η − 1)/(η + 1))² = F₀, F₀ ∈ [0, 1): η = (1 + √F₀)/(1 − √F₀); +inf
    at F₀ = 1."""
    r = np.sqrt(np.asarray(f0, dtype=float))
    return where_valid(r < 1.0, [r], lambda x: (1.0 + x) / (1.0 - x), np.inf)


def dielectric_reflectance(cos_theta, eta):
    """Exact unpolarised Fresnel reflectance F = (r_s² + r_p²)/2 for light from index 1
    onto index η ≥ 1 (Born & Wolf sec. 1.5.2; pbrt-v4 FrDielectric).

    With c = cos θ, d = η² − 1 = (η − 1)(η + 1) and g = η cos θ_t = √(d + c²), the amplitude
    ratios are written with numerator and denominator multiplied by the denominator:

        r_s = −d / (d + 2c(c + g)),
        r_p = d((η² + 1)c² − 1) / (d + c² + η²c(η²c + 2g)).

    Nothing cancels when η → 1 (d is formed from η − 1); at c = 0 both are −1 exactly, so
    F(0) = 1 exactly. A denominator is 0 only when d = 0 and c = 0 (or they underflow): no
    interface, F = 0 (its limit along c). η = +inf (a perfect mirror, F₀ = 1) gives F = 1.
    (derivation: docs/fresnel.md §1)
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



@FRESNELS.register
class Dielectric(Fresnel):
    name = "dielectric"
    label = "Dielectric (exact)"
    description = "Exact unpolarised Fresnel reflectance of a dielectric of index η seen from air."
    reference = "Born & Wolf, Principles of Optics, sec. 1.5.2"
    params = (IOR_DIELECTRIC,)
    menu_order = 2

    def F(self, cos_theta_d):
        return dielectric_reflectance(cos_theta_d, self.ior)

    F_formula = Formula(
        "F_dielectric", ("c",),
        "sel(eta < INF(), sel(and_(den_s > 0.0, den_p > 0.0), 0.5 * ((d / den_s) * (d / den_s) + "
        "(d * ((e2 + 1.0) * x * x - 1.0) / den_p) * (d * ((e2 + 1.0) * x * x - 1.0) / den_p)), 0.0), 1.0)",
        body=(("x", "clamp(c, 0.0, 1.0)"), ("e2", "eta * eta"), ("d", "(eta - 1.0) * (eta + 1.0)"),
              ("g", "sqrt(d + x * x)"), ("den_s", "d + 2.0 * x * (x + g)"),
              ("den_p", "d + x * x + e2 * x * (e2 * x + 2.0 * g)")),
        p=("eta",),
        doc="(r_s² + r_p²)/2, r_s = −d/(d + 2c(c + g)), r_p = d((η² + 1)c² − 1)/(d + c² + η²c(η²c + 2g)),\n"
            "d = η² − 1, g = √(d + c²) (Born & Wolf sec. 1.5.2, expanded so nothing cancels as η → 1).")
