"""μΛ from the general Smith integral, tabulated once per NDF shape and interpolated.

For a slope-space NDF, h = μΛ/s is a function of a = μ/s alone once the shape is fixed (for
GTR and Blinn-Phong, not shape-invariant, the shape includes α). It is tabulated at
TABLE_NODES points uniform in x = ln a over [A_MIN, A_MAX] from the reference integral
(smith_integral.py), value and exact slope, and interpolated by a cubic Hermite in x
(monotone PCHIP, Fritsch & Carlson 1980, where the exact slopes would leave the monotone
region). Outside the table: linear from the exact grazing value h(0) below A_MIN, and
h(A_MAX)·A_MAX/a above A_MAX. |ΔG1| ≤ TABLE_G1_ERROR (1e-9) against the direct integral
(tests/robustness/test_smith_numeric.py); a lookup costs about a closed-form Λ. ``smith``
uses it where Λ has no closed form, ``smith_numeric`` for every NDF. A
:class:`LambdaTable` is plain arrays on a uniform grid, which a compiled loop evaluates
as :meth:`LambdaTable.h` does; the nodes' integrals come from a compiled loop once
app/kernels has the NDF's (``COMPILED_H``), from numpy before. (derivation: docs/smith.md §3)
"""
from __future__ import annotations

from dataclasses import dataclass
from functools import lru_cache

import numpy as np
from scipy.interpolate import CubicHermiteSpline, PchipInterpolator

from .numeric import where_valid
from .smith_integral import h_and_slope

#: NDF class → h_and_slope(ndf, a) compiled (app/kernels registers one when an NDF's loops
#: are ready; it may answer None, e.g. while compiled loops are switched off): the same
#: rule as smith_integral.h_and_slope, whose numpy form serves otherwise.
COMPILED_H: dict = {}

TABLE_NODES = 2049
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
    a = np.exp(x)
    h, dh_da = _h_and_slope(ndf, np.concatenate([a, [0.0]]))
    h, dh_da, h0 = h[:-1], dh_da[:-1], float(h[-1])
    flushed = h < H_FLUSH
    h, dh_dx = np.where(flushed, 0.0, h), np.where(flushed, 0.0, a * dh_da)
    # A cubic Hermite with the exact slopes: |ΔG1| ≤ 4e-10 where PCHIP's estimated
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


def _h_and_slope(ndf, a):
    compiled = COMPILED_H.get(type(ndf))
    out = compiled(ndf, a) if compiled is not None else None
    return out if out is not None else h_and_slope(ndf, a)


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
