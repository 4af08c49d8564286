"""Blinn-Phong, normalised, parameterised by its Beckmann-equivalent α_b.

D(m) = (α_p + 2)/(2π) (n·m)^{α_p},  α_p = 2/α_b² − 2  (Walter et al. 2007, eq. 30, 33).

Not shape-invariant, so isotropic only. Its Smith Λ has no closed form; ``smith`` uses
Walter 2007's substitution a = √(0.5 α_p + 1)/tanθ into Beckmann's Λ, which is Beckmann's
Λ at α_b exactly: an approximation of Blinn-Phong's own Smith Λ (``masking=smith_numeric``
shows the difference). Tail mass in stretched slopes r̃ = tanθ/α_b:
1 − C(r̃) = (1 + α_b² r̃²)^{−1/α_b²} (the mass of normals beyond θ, cos^{α_p+2}θ).
(derivation: docs/ndfs.md §5)

References: Blinn 1977; Walter et al. 2007, "Microfacet Models for Refraction through
Rough Surfaces", eq. 30-32 (normalisation, α_p, Λ).
"""
from __future__ import annotations

import math

import numpy as np

from ..formula import Formula
from ..scalar import scalar
from .base import NDFS, SlopeSpaceNDF
from .beckmann import BECKMANN_MU_LAMBDA, beckmann_mu_Lambda


@NDFS.register
class BlinnPhong(SlopeSpaceNDF):
    name = "blinn_phong"
    label = "Blinn-Phong"
    menu_order = 2
    description = ("Normalised (cos θ_m)^α_p with α_p = 2/α² − 2 (α the Beckmann-equivalent "
                   "roughness); isotropic only.")
    reference = "Blinn 1977; Walter et al. 2007, eq. 30-33"
    shape_invariant = False
    anisotropic = False
    smith_exact = False
    derived_doc = {"alpha_p": "2/alpha^2 - 2, the Phong exponent (Walter et al. 2007, eq. 33)"}

    @property
    def alpha_p(self) -> float:
        """The Phong exponent (Walter et al. 2007, eq. 33)."""
        return 2.0 / self.alpha_x ** 2 - 2.0

    def derived(self) -> dict:
        return {"alpha_p": self.alpha_p}

    @property
    def tail_beta(self) -> float:
        # v = (1 + α² r̃²)^{−1/α²} ~ r̃^{−2/α²}
        return 0.5 * self.alpha_x ** 2

    def _D(self, mz, q2):
        # α_b² D; mz^α_p is 1 at α_p = 0 (α_b = 1, the uniform cosine lobe) and
        # underflows smoothly for large α_p.
        return self.alpha_x ** 2 * (self.alpha_p + 2.0) / (2.0 * np.pi) * np.power(mz, self.alpha_p)

    def _mu_Lambda(self, mu, s):
        return beckmann_mu_Lambda(mu, s)

    def radial_ccdf(self, r2):
        a2 = self.alpha_x ** 2
        return np.exp(-np.log1p(a2 * r2) / a2)

    def radial_ccdf_inv(self, v):
        a2 = self.alpha_x ** 2
        return np.expm1(-a2 * np.log(v)) / a2

    def radial_cdf(self, r2):
        a2 = self.alpha_x ** 2
        return -np.expm1(-np.log1p(a2 * r2) / a2)

    def radial_cdf_inv(self, u):
        a2 = self.alpha_x ** 2
        return np.expm1(-a2 * np.log1p(-u)) / a2

    # p = (α², α_p, α² (α_p + 2)/(2π))
    def kernel_params(self):
        a2 = self.alpha_x ** 2
        return (a2, self.alpha_p, a2 * (self.alpha_p + 2.0) / (2.0 * np.pi))

    # pow(0, 0) is undefined in GLSL: α_p = 0 (α = 1) is the constant lobe, written apart
    D_formula = Formula(
        "D_blinn_phong", ("mz", "q2"), "sel(alpha_p > 0.0, norm * pow(max(mz, 0.0), alpha_p), norm)",
        p=("a2", "alpha_p", "norm"),
        doc="Blinn-Phong: α² D = α² (α_p + 2)/(2π) (n·m)^α_p, α_p = 2/α² − 2 (Blinn 1977; Walter et al. 2007, eq. 30).")
    # Walter 2007's substitution: Beckmann's Λ (shape-invariant, α enters through s)
    mu_Lambda_formula = BECKMANN_MU_LAMBDA

    @staticmethod
    @scalar
    def radial_ccdf_scalar(r2, p):
        return math.exp(-math.log1p(p[0] * r2) / p[0])

    @staticmethod
    @scalar
    def radial_cdf_inv_scalar(u, p):
        return math.expm1(-p[0] * math.log1p(-u)) / p[0]

    @staticmethod
    @scalar
    def radial_ccdf_inv_scalar(v, p):
        return math.expm1(-p[0] * math.log(v)) / p[0]
