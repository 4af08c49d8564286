"""Exact unpolarised Fresnel reflectance of a metal of complex index η + iκ seen from air.

References
----------
Born & Wolf, "Principles of Optics", sec. 14.2; pbrt-v4 (2023), sec. 9.3.6 "FrComplex";
Johnson & Christy 1972, Phys. Rev. B 6, 4370 (gold).
"""
from __future__ import annotations

import math

import numpy as np

from ..numeric import where_valid
from ..params import Param
from ..formula import Formula
from ..scalar import scalar
from .base import FRESNELS, Fresnel, _cos, clip_cos_scalar

# Gold at λ = 548.6 nm: n = 0.43, k = 2.455 (Johnson & Christy 1972, Phys. Rev. B 6, 4370,
# table I); F₀ = ((n−1)² + k²)/((n+1)² + k²) ≈ 0.787.
IOR_CONDUCTOR = Param("ior", "η (real part of the index)", 0.01, 10.0, 0.43,
                      "Real part η of the complex index η + iκ; default: gold at 548.6 nm "
                      "(Johnson & Christy 1972).")
K_CONDUCTOR = Param("k", "κ (extinction coefficient)", 0.0, 20.0, 2.455,
                    "Imaginary part κ of the complex index η + iκ; default: gold at 548.6 nm "
                    "(Johnson & Christy 1972).")



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
    return _unpolarised(np.sqrt(a2), b2, c, c2, s2, A)


@scalar
def _unpolarised(a, b2, c, c2, s2, A):
    """(R_s + R_p)/2 from a, b² (arrays or numbers: both paths share it)."""
    Rs = ((a - c) ** 2 + b2) / ((a + c) ** 2 + b2)
    u = A * c2 + s2 * s2
    v = 2.0 * a * c * s2
    Rp = Rs * (u - v) / (u + v)
    return 0.5 * (Rs + Rp)



@FRESNELS.register
class Conductor(Fresnel):
    name = "conductor"
    label = "Conductor (exact)"
    description = ("Exact unpolarised Fresnel reflectance of a metal of complex index η + iκ "
                   "seen from air (one wavelength).")
    reference = "Born & Wolf, Principles of Optics, sec. 14.2; pbrt-v4 FrComplex"
    params = (IOR_CONDUCTOR, K_CONDUCTOR)
    menu_order = 3

    def F(self, cos_theta_d):
        return conductor_reflectance(cos_theta_d, self.ior, self.k)

    F_formula = Formula(
        "F_conductor", ("c",), "0.5 * (Rs + Rs * (u - q) / (u + q))",
        body=(("x", "clamp(c, 0.0, 1.0)"), ("c2", "x * x"), ("s2", "max(1.0 - c2, 0.0)"),
              ("t0", "eta * eta - kappa * kappa - s2"), ("ek", "eta * kappa"), ("A", "sqrt(t0 * t0 + 4.0 * ek * ek)"),
              ("a2", "sel(t0 >= 0.0, 0.5 * (A + abs(t0)), sel(A - t0 > 0.0, 2.0 * ek * ek / (A - t0), 0.0))"),
              ("b2", "sel(t0 >= 0.0, sel(A + t0 > 0.0, 2.0 * ek * ek / (A + t0), 0.0), 0.5 * (A - t0))"),
              ("a", "sqrt(a2)"), ("Rs", "((a - x) * (a - x) + b2) / ((a + x) * (a + x) + b2)"),
              ("u", "A * c2 + s2 * s2"), ("q", "2.0 * a * x * s2")),
        p=("eta", "kappa"),
        doc="Born & Wolf sec. 14.2 in real arithmetic (pbrt-v4's FrComplex): a + ib = √((η + iκ)² − sin²θ),\n"
            "A = a² + b²; a² (or b²) as 2η²κ²/(A ∓ t₀) where A ± t₀ would cancel. κ ≫ η and η = 0 work.")
