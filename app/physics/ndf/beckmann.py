"""Beckmann (seed 000 (3-28)..(3-30)).

References
----------
Beckmann & Spizzichino 1963; Walter et al. 2007, eq. 25-27; Heitz 2014, eq. 83-84.
"""
from __future__ import annotations

import numpy as np
from scipy.special import erfcx

from . import register
from .base import ShapeInvariantNDF
from ..numeric import where_valid

SQRT_PI = np.sqrt(np.pi)

# Below A_SERIES the bracket 1/√π − a·erfcx(a) is computed directly; it loses about
# 2a² ulps to cancellation, i.e. ≤ 1.4e-14 relative at a = 8. From A_SERIES on, the
# asymptotic series with SERIES_TERMS terms is used: its truncation error is about the
# next term, (2K+1)!!/(2a²)^(K+1) ≈ 7e-20 relative at a = 8, K = 20.
# (An earlier 8-term series from a = 6 was only good to 4e-8: found by an mpmath test.)
A_SERIES = 8.0
SERIES_TERMS = 20


def _bracket_direct(a):
    return 1.0 / SQRT_PI - a * erfcx(a)


def _bracket_series(a):
    # 1/√π − a·erfcx(a) = (1/√π) Σ_{k≥1} (−1)^{k+1} (2k−1)!! / (2^k a^{2k})
    # (Abramowitz & Stegun 7.1.23), SERIES_TERMS terms.
    x = 1.0 / (2.0 * a * a)
    total, term = np.zeros_like(a), np.ones_like(a)
    for k in range(1, SERIES_TERMS + 1):
        term = term * x * (2 * k - 1) if k > 1 else x
        total = total + (term if k % 2 else -term)
    return total / SQRT_PI


def beckmann_mu_Lambda(mu, s):
    """μΛ for the Beckmann slope distribution, a = μ/s.

    Λ(a) = (erf a − 1)/2 + e^{−a²}/(2a√π) (3-30). Times μ, with
    erf a − 1 = −erfc a = −erfcx(a) e^{−a²}:  μΛ = (s e^{−a²}/2)(1/√π − a·erfcx(a)).
    s = 0 is normal incidence, where Λ = 0.
    """
    def formula(mu, s):
        a = mu / s
        bracket = where_valid(a < A_SERIES, [a], _bracket_direct, 0.0) \
            + where_valid(a >= A_SERIES, [a], _bracket_series, 0.0)
        return 0.5 * s * np.exp(-a * a) * bracket
    return where_valid(s > 0, [mu, s], formula, 0.0)


@register
class Beckmann(ShapeInvariantNDF):
    name = "beckmann"
    label = "Beckmann"
    description = "Gaussian slope distribution (Beckmann-Spizzichino); short tails."
    menu_order = 1
    reference = "Walter et al. 2007, eq. 25-27; Heitz 2014, eq. 83"

    @property
    def tail_beta(self) -> float:
        return 0.0  # v = e^{−r̃²}: r̃ grows like √(−ln v)

    def _D(self, mz, q2):
        # D = exp(−tan²θ_m (cos²φ/α_x² + sin²φ/α_y²)) / (π α_x α_y cos⁴θ_m); the
        # exponent is −q²/mz². Limit at mz = 0 is 0; below mz = 1e-154 mz⁴ underflows
        # while the exponential is already 0.
        return where_valid(mz > 0, [mz, q2],
                           lambda z, q: np.exp(-q / (z * z)) / (np.pi * z ** 4), 0.0)

    def _mu_Lambda(self, mu, s):
        return beckmann_mu_Lambda(mu, s)

    def radial_cdf(self, r2):
        return -np.expm1(-r2)

    def radial_cdf_inv(self, u):
        return -np.log1p(-u)

    def radial_ccdf(self, r2):
        return np.exp(-r2)

    def radial_ccdf_inv(self, v):
        return -np.log(v)
