"""Oren–Nayar, the qualitative model (Oren & Nayar 1994, "Generalization of Lambert's
Reflectance Model", eq. 30):

f_d = ρ/π (A + B max(0, cos(φ_l − φ_v)) sin α tan β), α = max(θ_l, θ_v), β = min(θ_l, θ_v),
A = 1 − 0.5 σ²/(σ² + 0.33), B = 0.45 σ²/(σ² + 0.09), σ the standard deviation of the
facets' slope angle in radians. The geometric factor is max(0, s)/max(μ_l, μ_v) with
s = l·v − μ_l μ_v. Reciprocal. Loses energy (no inter-reflection): E_d(1, μ) < 1 for σ > 0.
"""
from __future__ import annotations

import math

import numpy as np

from ..params import Param
from ..formula import Formula
from .base import DIFFUSES, F_D_ARGS, Diffuse, s_over_t, times_rho

SIGMA = Param("sigma", "σ (facet slope deviation)", 0.0, 0.5 * math.pi, 0.3,
              "Standard deviation of the facet slope angle of Oren–Nayar's V-groove surface.",
              unit="rad")


def coefficients(sigma: float) -> tuple[float, float]:
    """(A, B) of Oren & Nayar 1994, eq. 30."""
    s2 = sigma * sigma
    return 1.0 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09)


@DIFFUSES.register
class OrenNayar(Diffuse):
    name = "oren_nayar"
    label = "Oren–Nayar (qualitative)"
    description = ("Rough diffuse from V-groove facets: f_d = ρ/π (A + B max(0, cos Δφ) sin α tan β); "
                   "flatter than Lambert, brighter toward the light; loses the inter-reflected energy.")
    reference = "Oren & Nayar 1994, eq. 30"
    params = (SIGMA,)
    menu_order = 3

    def f(self, rho, mu_l, mu_v, l_dot_v):
        A, B = coefficients(self.sigma)
        ratio = s_over_t(mu_l, mu_v, l_dot_v)
        geometric = B * ratio if B > 0 else np.zeros_like(ratio)   # σ = 0: Lambert
        return times_rho(rho, (A + geometric) / np.pi)

    def kernel_params(self):
        return coefficients(self.sigma)

    f_formula = Formula(
        "fd_oren_nayar", F_D_ARGS,
        "sel(rho == 0.0, 0.0, sel(t > 0.0, rho * (A + B * s / t) / PI, sel(and_(s > 0.0, B > 0.0), INF(), rho * A / PI)))",
        body=(("s", "max(l_dot_v - mu_l * mu_v, 0.0)"), ("t", "max(mu_l, mu_v)")),
        p=("A", "B"), consts=(("PI", math.pi, "π"),),
        doc="Oren & Nayar 1994, eq. 30: f_d = ρ/π (A + B max(0, s)/max(μ_l, μ_v)), s = l·v − μ_l μ_v;\n"
            "+∞ where both directions graze with s > 0 (its limit).")
