"""μΛ from the general Smith integral, tabulated once per NDF shape and interpolated.

For an NDF whose Λ has no closed form (GTR, exponential power), h = μΛ/s is a function
of a = μ/s alone once the shape is fixed (for GTR the shape includes α, since it is not
shape-invariant). It is tabulated at TABLE_NODES points uniform in x = ln a over
[A_MIN, A_MAX] with the reference integral (smith_integral.py) and interpolated by a
monotone cubic (PCHIP) in x. Uniform in ln a because GTR at small α changes character at
a ~ 1/α (where tanθ ~ 1): nodes uniform in a/(1 + a) were 50% apart there and missed
by 1e-3 in G1 at α = 1e-3 (found by test_zoo.py); in ln a the spacing is 1.3%.

Outside the table: below A_MIN, linear from the exact grazing value h(0) (a horizontal
direction is tabulated too: E(μ = 0) = 1 for height-correlated G2 depends on it); above A_MAX,
h(A_MAX)·A_MAX/a, exact for the r̃⁻⁴ tails of GTR (Λ ~ a⁻²) and below 1e-300 for the
exponential ones. Measured against the direct integral: |ΔG1| ≤ 1e-8
(tests/physics/test_zoo.py asks 1e-5, the issue's bound).

Tables are cached (bounded): building one costs TABLE_NODES × ORDER integrand
evaluations, about 30 ms.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.interpolate import PchipInterpolator

from .numeric import where_valid
from .smith_integral import mu_Lambda_numeric

TABLE_NODES = 2049
A_MIN, A_MAX = 1e-5, 1e7
CACHE_SIZE = 64
H_FLUSH = 1e-280


@lru_cache(maxsize=CACHE_SIZE)
def _table(ndf_class, alpha: float, shape: tuple):
    """(h(0), h at A_MIN, interpolant of h in ln a)."""
    ndf = ndf_class(alpha, None, **dict(shape))
    a = np.exp(np.linspace(np.log(A_MIN), np.log(A_MAX), TABLE_NODES))
    # Unit directions in the x-z plane with μ/(α sinθ) = a: tanθ = 1/(α a); the last
    # one is horizontal (a = 0, the grazing limit).
    sin_t = np.append(1.0 / np.sqrt(1.0 + (alpha * a) ** 2), 1.0)
    mu = np.append(alpha * a, 0.0) * sin_t
    w = np.stack([sin_t, np.zeros_like(sin_t), mu], axis=-1)
    h = mu_Lambda_numeric(ndf, w) / (alpha * sin_t)
    # Below H_FLUSH, h changes G1 by less than that; flushed to 0, the table has flat
    # zero runs instead of denormal slopes (PCHIP divides by its slopes).
    h = np.where(h < H_FLUSH, 0.0, h)
    # PCHIP, not a cubic spline: h falls monotonically (to 1e-300 and below for the
    # exponential tails) and a spline overshoots below 0 there (μΛ < 0 at α = 1e-3,
    # found by test_extremes); PCHIP keeps monotonicity and positivity.
    return float(h[-1]), float(h[0]), PchipInterpolator(np.log(a), h[:-1])


def mu_Lambda_tabulated(ndf, mu, s) -> np.ndarray:
    """μΛ for ``ndf`` (an isotropic slope-space NDF or a shape-invariant one) at (μ, s)."""
    shape = tuple((p.name, getattr(ndf, p.name)) for p in ndf.shape_params)
    alpha = ndf.alpha_x if not ndf.shape_invariant else 1.0
    h0, h_min, interpolant = _table(type(ndf), alpha, shape)

    def h_of(m, ss):
        a = m / ss
        h = interpolant(np.log(np.clip(a, A_MIN, A_MAX)))
        # a < A_MIN: linear between the exact grazing value h(0) and h(A_MIN) (h is
        # smooth at 0, so the error is O(A_MIN²)); a > A_MAX: the r̃⁻⁴-tail law.
        h = np.where(a < A_MIN, h0 + (h_min - h0) * (a / A_MIN), h)
        return ss * np.where(a > A_MAX, h * (A_MAX / np.maximum(a, A_MAX)), h)
    # s = 0 is normal incidence (no masking); μ = 0 is a = 0, the flat end.
    return where_valid(s > 0, [mu, s], h_of, 0.0)
