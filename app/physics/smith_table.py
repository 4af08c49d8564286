"""μΛ from the general Smith integral, tabulated once per NDF shape and interpolated.

For a slope-space NDF, h = μΛ/s is a function of a = μ/s alone once the shape is fixed (for
GTR and Blinn-Phong, not shape-invariant, the shape includes α). It is tabulated at
TABLE_NODES points uniform in x = ln a over [A_MIN, A_MAX], value and slope, interpolated
by a cubic Hermite in x, monotone PCHIP (Fritsch & Carlson 1980) where the slopes would
leave the monotone region. The reference integral (smith_integral.py) is computed at an
adaptive subset of the nodes, a quintic Hermite giving the rest (:func:`node_values`,
within QUINTIC_G1_ERROR in G1). Outside the table: linear from the exact h(0) below A_MIN,
h(A_MAX)·A_MAX/a above A_MAX. |ΔG1| ≤ TABLE_G1_ERROR (1e-9) against the direct integral
(tests/robustness/test_smith_numeric.py). ``smith`` uses it where Λ has no closed form,
``smith_numeric`` for every NDF; a compiled loop evaluates it as :meth:`LambdaTable.h`
does, and integrates its nodes once app/kernels has the NDF's loops (``COMPILED_H``).
(derivation: docs/smith.md §3)
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.interpolate import CubicHermiteSpline, PchipInterpolator

from .numeric import where_valid
from .smith_integral import h_derivatives

#: NDF class → h_derivatives(ndf, a) compiled (app/kernels registers one when an NDF's loops
#: are ready; it may answer None, e.g. while compiled loops are switched off): the same
#: rule as smith_integral.h_derivatives, whose numpy form serves otherwise.
COMPILED_H: dict = {}

TABLE_NODES = 2049
#: the integrals are computed at every COARSE_STRIDE-th node at least (node_values)
COARSE_STRIDE = 16
#: the quintic's share of TABLE_G1_ERROR, and the margin its midpoint check keeps (a
#: halved interval's error is ~1/64 of its parent's where h is smooth)
QUINTIC_G1_ERROR = 2e-11
REFINE_MARGIN = 16.0
REFINE_RELATIVE = 1e-3
A_MIN, A_MAX = 1e-5, 1e7
#: tables kept per process; each holds 4 × TABLE_NODES floats (64 kB)
CACHE_SIZE = 64
#: below this h changes G1 by less than that; flushed to 0, the table has flat zero runs
#: instead of denormal slopes (PCHIP divides by its slopes)
H_FLUSH = 1e-280
#: the stated interpolation error in G1 (measured ≤ 4e-10 at every NDF's parameter
#: extremes; the test asks this)
TABLE_G1_ERROR = 1e-9


@dataclass(frozen=True)
class LambdaTable:
    """h(a) = μΛ/s of one NDF shape: a cubic per interval of a uniform grid in x = ln a.

    ``coefficients[:, i]`` are (c₀, c₁, c₂, c₃) of h = ((c₀t + c₁)t + c₂)t + c₃ with
    t = x − x₀ − i·dx on interval i (PCHIP's local power basis). ``h0`` is the exact
    grazing value h(0), ``h_min`` = h(A_MIN)."""
    x0: float
    dx: float
    coefficients: np.ndarray   # (4, TABLE_NODES − 1), read-only
    h0: float
    h_min: float
    a_min: float = A_MIN
    a_max: float = A_MAX

    def _cubic(self, x):
        i = np.clip(np.floor((x - self.x0) / self.dx), 0, self.coefficients.shape[1] - 1).astype(np.intp)
        t = x - (self.x0 + i * self.dx)
        c = self.coefficients
        return ((c[0, i] * t + c[1, i]) * t + c[2, i]) * t + c[3, i]

    def h(self, a) -> np.ndarray:
        """h(a) for a ≥ 0, with the end laws of the module docstring."""
        a = np.asarray(a, dtype=float)
        h = self._cubic(np.log(np.clip(a, self.a_min, self.a_max)))
        # a < A_MIN: linear between h(0) and h(A_MIN) (h is smooth at 0: error O(A_MIN²));
        # a > A_MAX: the r̃⁻⁴-tail law.
        h = np.where(a < self.a_min, self.h0 + (self.h_min - self.h0) * (a / self.a_min), h)
        return np.where(a > self.a_max, h * (self.a_max / np.maximum(a, self.a_max)), h)

    def mu_Lambda(self, mu, s) -> np.ndarray:
        """μΛ = s·h(μ/s); s = 0 is normal incidence (no masking), μ = 0 is a = 0."""
        return where_valid(np.asarray(s) > 0, [mu, s], lambda m, ss: ss * self.h(m / ss), 0.0)


@lru_cache(maxsize=CACHE_SIZE)
def _table(ndf_class, alpha: float, shape: tuple) -> LambdaTable:
    # Shape-invariant NDFs are tabulated at α = 1 (a = μ/s carries α); the others at their α.
    ndf = ndf_class(alpha, None, **dict(shape))
    x = np.linspace(np.log(A_MIN), np.log(A_MAX), TABLE_NODES)
    h, dh_dx, h0 = node_values(ndf, x)
    flushed = h < H_FLUSH
    h, dh_dx = np.where(flushed, 0.0, h), np.where(flushed, 0.0, dh_dx)
    # A cubic Hermite with the slopes of the integral: |ΔG1| ≤ 4e-10 where PCHIP's estimated
    # slopes gave 6e-8 (exponential power, p = 4). In the steep exponential tails it can
    # dip below 0; on every interval outside Fritsch & Carlson's monotone region
    # (α² + β² ≤ 9 for the slope/secant ratios) PCHIP's cubic is taken instead, which
    # keeps h monotone and positive there (h < 1e-6 on those intervals: Beckmann, p = 4).
    hermite = CubicHermiteSpline(x, h, dh_dx).c
    pchip = PchipInterpolator(x, h).c
    secant = np.diff(h) / np.diff(x)
    with np.errstate(divide="ignore", invalid="ignore"):
        ratio2 = (dh_dx[:-1] ** 2 + dh_dx[1:] ** 2) / secant ** 2
    monotone = (secant != 0) & (ratio2 <= 9.0) | (dh_dx[:-1] == 0) & (dh_dx[1:] == 0)
    coefficients = np.where(monotone, hermite, pchip)
    coefficients.flags.writeable = False
    return LambdaTable(float(x[0]), float(x[1] - x[0]), coefficients, h0, float(h[0]))


def node_values(ndf, x):
    """h and dh/dx at the uniform nodes x = ln a, and h(0). The integrals (value, slope,
    curvature) are computed at every COARSE_STRIDE-th node; each interval is halved
    while its quintic Hermite (:func:`quintic_hermite`), checked at its midpoint against
    the integral there, misses it by more than QUINTIC_G1_ERROR × REFINE_MARGIN in G1
    (|Δh| a/(a + h)²: Λ = h/a) or by REFINE_RELATIVE of h (the exponential tails, where
    the table's monotone shape rests on h's relative accuracy). The other nodes take the
    quintic of their smallest computed interval."""
    a = np.exp(x)
    known = np.zeros(x.size, dtype=bool)
    h, h_x, h_xx = np.zeros(x.size), np.zeros(x.size), np.zeros(x.size)

    def integrate(nodes):
        v, d1, d2 = _h_derivatives(ndf, a[nodes])
        h[nodes], h_x[nodes], h_xx[nodes] = v, a[nodes] * d1, a[nodes] * d1 + a[nodes] ** 2 * d2
        known[nodes] = True

    stride = COARSE_STRIDE
    integrate(np.arange(0, x.size, stride))
    left = np.arange(0, x.size - 1, stride)
    while stride > 1 and left.size:
        half = stride // 2
        mid = left + half
        integrate(mid)
        guess = quintic_hermite(x[left], x[left + stride], *(f[left] for f in (h, h_x, h_xx)),
                                *(f[left + stride] for f in (h, h_x, h_xx)), x[mid])[0]
        miss = np.abs(guess - h[mid])
        refine = (miss * a[mid] / (a[mid] + h[mid]) ** 2 > QUINTIC_G1_ERROR / REFINE_MARGIN) | (
            (miss > REFINE_RELATIVE * h[mid]) & (h[left] >= H_FLUSH))
        left = np.concatenate([left[refine], mid[refine]])
        stride = half
    values, slopes = _fill(x, known, h, h_x, h_xx)
    # h is positive and falls (smith_table's interpolant relies on it): an interval whose
    # quintic breaks that anywhere above H_FLUSH has its nodes integrated.
    live = values[:-1] >= H_FLUSH
    broken = np.flatnonzero(~known & ((values < 0) | np.append(live & (np.diff(values) > 0), False)))
    if broken.size:
        k = np.flatnonzero(known)
        i = np.searchsorted(k, broken)
        span = np.unique(np.concatenate([np.arange(k[j - 1] + 1, k[j]) for j in np.unique(i)]))
        integrate(span)
        values, slopes = _fill(x, known, h, h_x, h_xx)
    h0 = float(_h_derivatives(ndf, np.zeros(1))[0][0])
    return values, slopes, h0


def _fill(x, known, h, h_x, h_xx):
    """The integrals at the ``known`` nodes, the quintic of their interval elsewhere."""
    k = np.flatnonzero(known)
    i = np.clip(np.searchsorted(k, np.arange(x.size), side="right") - 1, 0, k.size - 2)
    lo, hi = k[i], k[i + 1]
    values, slopes = quintic_hermite(x[lo], x[hi], h[lo], h_x[lo], h_xx[lo], h[hi], h_x[hi],
                                     h_xx[hi], x)
    values[known], slopes[known] = h[known], h_x[known]
    return values, slopes


def quintic_hermite(x0, x1, y0, dy0, d2y0, y1, dy1, d2y1, x):
    """The quintic Hermite interpolant on [x0, x1] of (y, y', y'') given at both ends,
    and its derivative, at ``x`` (Burden & Faires, Numerical Analysis §3.4; error
    ≤ Δ⁶ max|y⁽⁶⁾|/46080 on an interval Δ, largest at its midpoint)."""
    d = x1 - x0
    t = (x - x0) / d
    t2, t3 = t * t, t * t * t
    t4, t5 = t3 * t, t3 * t2
    basis = (1 - 10 * t3 + 15 * t4 - 6 * t5, t - 6 * t3 + 8 * t4 - 3 * t5,
             0.5 * (t2 - 3 * t3 + 3 * t4 - t5), 10 * t3 - 15 * t4 + 6 * t5,
             -4 * t3 + 7 * t4 - 3 * t5, 0.5 * (t3 - 2 * t4 + t5))
    d_basis = (-30 * t2 + 60 * t3 - 30 * t4, 1 - 18 * t2 + 32 * t3 - 15 * t4,
               0.5 * (2 * t - 9 * t2 + 12 * t3 - 5 * t4), 30 * t2 - 60 * t3 + 30 * t4,
               -12 * t2 + 28 * t3 - 15 * t4, 0.5 * (3 * t2 - 8 * t3 + 5 * t4))
    ends = (y0, d * dy0, d * d * d2y0, y1, d * dy1, d * d * d2y1)
    value = sum(b * e for b, e in zip(basis, ends))
    return value, sum(b * e for b, e in zip(d_basis, ends)) / d


def _h_derivatives(ndf, a):
    compiled = COMPILED_H.get(type(ndf))
    out = compiled(ndf, a) if compiled is not None else None
    return out if out is not None else h_derivatives(ndf, a)


def lambda_table(ndf) -> LambdaTable:
    """The (cached) table of ``ndf``'s shape: α enters only when not shape-invariant."""
    shape = tuple((p.name, getattr(ndf, p.name)) for p in ndf.shape_params)
    alpha = ndf.alpha_x if not ndf.shape_invariant else 1.0
    return _table(type(ndf), alpha, shape)


def mu_Lambda_tabulated(ndf, mu, s) -> np.ndarray:
    """μΛ for ``ndf`` (an isotropic slope-space NDF or a shape-invariant one) at (μ, s)."""
    return lambda_table(ndf).mu_Lambda(mu, s)


def mu_Lambda_smith_numeric(ndf, w) -> np.ndarray:
    """μΛ(ω) of the general Smith integral through the table, for any direction
    (``masking=smith_numeric``): 0 below the horizon, as the direct integral."""
    w = np.asarray(w, dtype=float)
    mu = w[..., 2]
    return where_valid(mu >= 0, [mu, ndf.stretched_sin(w)], lambda m, s: mu_Lambda_tabulated(ndf, m, s), 0.0)
