"""Beckmann.

References
----------
Beckmann & Spizzichino 1963; Walter et al. 2007, eq. 25-27; Heitz 2014, eq. 83-84;
Heitz & d'Eon 2014, "Importance Sampling Microfacet-Based BSDFs using the Distribution
of Visible Normals", EGSR, sec. 4 (visible normals).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.special import erfc, erfcx, ndtri

from ..formula import Formula
from ..numeric import where_valid
from ..scalar import scalar
from ..vectors import slopes_to_normal, unit
from .base import NDFS, ShapeInvariantNDF

SQRT_PI = np.sqrt(np.pi)

# Below A_SERIES the bracket 1/√π − a·erfcx(a) is computed directly; it loses about
# 2a² ulps to cancellation, i.e. ≤ 1.4e-14 relative at a = 8. From A_SERIES on, the
# asymptotic series with SERIES_TERMS terms is used: its truncation error is about the
# next term, (2K+1)!!/(2a²)^(K+1) ≈ 7e-20 relative at a = 8, K = 20 (an 8-term series
# from a = 6 was only good to 4e-8, against mpmath).
A_SERIES = 8.0
SERIES_TERMS = 20

# Visible slopes: the 1-D marginal is bracketed in [−SLOPE_BRACKET, min(cot θ,
# SLOPE_BRACKET)]; its mass outside is erfc(8)/2 ≈ 6e-30, far below any test's reach.
SLOPE_BRACKET = 8.0
# Bisection halves the bracket (width ≤ 16) BISECTION_STEPS times: 16/2^60 ≈ 1.4e-17,
# below the spacing of doubles near the slopes that matter.
BISECTION_STEPS = 60


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

    Λ(a) = (erf a − 1)/2 + e^{−a²}/(2a√π) (Walter et al. 2007, eq. 27). Times μ, with
    erf a − 1 = −erfc a = −erfcx(a) e^{−a²}:  μΛ = (s e^{−a²}/2)(1/√π − a·erfcx(a)).
    s = 0 is normal incidence, where Λ = 0.
    """
    def formula(mu, s):
        a = mu / s
        bracket = where_valid(a < A_SERIES, [a], _bracket_direct, 0.0) \
            + where_valid(a >= A_SERIES, [a], _bracket_series, 0.0)
        return 0.5 * s * np.exp(-a * a) * bracket
    return where_valid(s > 0, [mu, s], formula, 0.0)


def _series_horner(terms: int) -> str:
    """Σ_{k=1}^{K} (−1)^{k+1} (2k−1)!! x^k in Horner form: x(1 − 3x(1 − 5x(1 − …)))."""
    inner = "1.0"
    for k in range(terms, 1, -1):
        inner = f"1.0 - {2 * k - 1}.0 * x * ({inner})"
    return f"x * ({inner})"


#: The one spelling of :func:`beckmann_mu_Lambda` for the kernels and the shaders: the same
#: two branches, the series in Horner form; the direct bracket is ≥ 0.0044 for a < 8 in
#: float64 (its max with 0 guards a float32 erfcx fit only).
#: Beckmann, BECKMANN_MZ_MIN: below this n·m, D = 0 in any float format: the exponent
#: −q²/mz² ≤ −(1 − mz²)/(α² mz²) < −9.9e5 for α ≤ 1, so exp underflows to 0 in float64
#: too, while mz⁴ in the denominator underflows in float32 (0/0) below mz ≈ 1e-10.
BECKMANN_MZ_MIN = 1e-3
BECKMANN_MU_LAMBDA = Formula(
    "muLambda_beckmann", ("mu", "s2"),
    "sel(s > 0.0, 0.5 * s * exp(-a * a) * sel(a < A_SERIES, max(INV_SQRT_PI - a * erfcx(a), 0.0), "
    "INV_SQRT_PI * series), 0.0)",
    body=(("s", "sqrt(s2)"), ("a", "mu / max(s, TINY)"), ("x", "1.0 / (2.0 * a * a)"), ("series", _series_horner(SERIES_TERMS))),
    consts=(("INV_SQRT_PI", 1.0 / math.sqrt(math.pi), "1/√π"),
            ("A_SERIES", A_SERIES, "from here on the asymptotic series (A&S 7.1.23)"),
            ("TINY", 1e-30, "s is > 0 where a is used; the floor only keeps the unused side finite")),
    doc="Beckmann's Smith μΛ, a = μ/s: (s e^(−a²)/2)(1/√π − a erfcx(a)) (Walter et al. 2007, eq. 27;\n"
        "Heitz 2014, eq. 84); from a = 8 the bracket's asymptotic series (A&S 7.1.23), 20 terms.")


def _slope_marginal_inv(cos_t, sin_t, u):
    """x̃ with density ∝ (cosθ − x̃ sinθ)⁺ e^{−x̃²}/√π (the visible slope along v's
    azimuth, α = 1; Heitz & d'Eon 2014, sec. 4). Its unnormalised CDF is
    A(x) = cosθ erfc(−x)/2 + sinθ e^{−x²}/(2√π) for x ≤ cot θ; A(x) = u·A(cot θ) is
    solved by bisection (A is increasing there)."""
    def A(x):
        return 0.5 * cos_t * erfc(-x) + sin_t * np.exp(-x * x) / (2.0 * SQRT_PI)

    cot = where_valid(sin_t > 0, [cos_t, sin_t], lambda c, s: c / s, np.inf)
    hi = np.minimum(cot, SLOPE_BRACKET)
    target = u * A(hi)
    lo = np.full_like(target, -SLOPE_BRACKET)
    hi = np.broadcast_to(hi, target.shape).copy()
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        below = A(mid) < target
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    return 0.5 * (lo + hi)


@NDFS.register
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

    D_formula = Formula(
        "D_beckmann", ("mz", "q2"),
        "sel(mz > BECKMANN_MZ_MIN, exp(-q2 / (mz * mz)) / (PI * mz * mz * mz * mz), 0.0)",
        consts=(("PI", math.pi, "π"),
                ("BECKMANN_MZ_MIN", BECKMANN_MZ_MIN, "below it D = 0 in float64 too; mz⁴ would underflow in float32")),
        doc="Beckmann: α_x α_y D = exp(−q²/mz²)/(π mz⁴) (Walter et al. 2007, eq. 25; Heitz 2014, eq. 83).")
    mu_Lambda_formula = BECKMANN_MU_LAMBDA

    @staticmethod
    @scalar
    def radial_ccdf_scalar(r2, p):
        return math.exp(-r2)

    @staticmethod
    @scalar
    def radial_cdf_inv_scalar(u, p):
        return -math.log1p(-u)

    @staticmethod
    @scalar
    def radial_ccdf_inv_scalar(v, p):
        return -math.log(v)

    def sample_visible(self, v, u):
        """Slope-space visible normals (Heitz & d'Eon 2014): stretch v, sample the slope
        along its azimuth from the visible marginal and the other from the Gaussian
        e^{−ỹ²}/√π (the α = 1 slopes are independent), rotate, unstretch."""
        V = unit(np.stack([self.alpha_x * v[..., 0], self.alpha_y * v[..., 1], v[..., 2]],
                          axis=-1))[..., None, :]
        sin_t = np.sqrt(V[..., 0] ** 2 + V[..., 1] ** 2)
        cos_t = V[..., 2]
        inv = where_valid(sin_t > 0, [sin_t], lambda s: 1.0 / s, 0.0)
        cos_p = np.where(sin_t > 0, V[..., 0] * inv, 1.0)
        sin_p = np.where(sin_t > 0, V[..., 1] * inv, 0.0)
        x = _slope_marginal_inv(cos_t, sin_t, u[..., 0])
        y = ndtri(u[..., 1]) / np.sqrt(2.0)                       # N(0, ½): e^{−y²}/√π
        xr = cos_p * x - sin_p * y
        yr = sin_p * x + cos_p * y
        return slopes_to_normal(self.alpha_x * xr, self.alpha_y * yr)
