"""The tabulated μΛ of ``smith_table.py`` as a float array and a scalar formula.

For an NDF whose Λ has no closed form, ``smith_table`` interpolates h = μΛ/s in ln a
(a = μ/s) by a monotone cubic (PCHIP). :func:`table_params` packs that table (the
grazing value, the ends, the breakpoints and the cubic's coefficients) into floats, and
:func:`tabulated_mu_Lambda_scalar` evaluates it for one point exactly as scipy's
``PPoly`` does (same interval, same order of operations), so a compiled loop and the
numpy path agree to rounding.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from . import smith_table
from .scalar import scalar

#: Floats before the breakpoints: h(0), h(A_MIN), A_MIN, A_MAX, number of intervals.
HEADER = 5


@lru_cache(maxsize=smith_table.CACHE_SIZE)
def _packed(ndf_class, alpha: float, shape: tuple) -> np.ndarray:
    h0, h_min, interpolant = smith_table._table(ndf_class, alpha, shape)
    x, c = interpolant.x, interpolant.c
    out = np.concatenate([[h0, h_min, smith_table.A_MIN, smith_table.A_MAX, x.size - 1],
                          x, c.ravel()])
    out.flags.writeable = False
    return out


def table_params(ndf) -> np.ndarray:
    """The table of ``ndf`` (as ``smith_table.mu_Lambda_tabulated`` chooses it), packed."""
    shape = tuple((p.name, getattr(ndf, p.name)) for p in ndf.shape_params)
    alpha = ndf.alpha_x if not ndf.shape_invariant else 1.0
    return _packed(type(ndf), alpha, shape)


@scalar
def tabulated_mu_Lambda_scalar(mu, s, p, at):
    """μΛ at (μ, s) from the table packed in ``p`` from index ``at``."""
    if not s > 0.0:
        return 0.0
    h0, h_min, a_min, a_max = p[at], p[at + 1], p[at + 2], p[at + 3]
    n = int(p[at + 4])
    xs = at + HEADER                 # breakpoints x[0..n]
    cs = xs + n + 1                  # coefficients c[k, i] at cs + k n + i
    a = mu / s
    xval = math.log(min(max(a, a_min), a_max))
    # the interval PPoly finds: the largest i ≤ n − 1 with x[i] ≤ xval
    i = min(max(int((xval - p[xs]) / (p[xs + n] - p[xs]) * n), 0), n - 1)
    while i > 0 and xval < p[xs + i]:
        i -= 1
    while i < n - 1 and xval >= p[xs + i + 1]:
        i += 1
    d = xval - p[xs + i]
    h, z = 0.0, 1.0
    for k in range(4):               # Σ c[3 − k, i] d^k, as PPoly sums it
        h = h + p[cs + (3 - k) * n + i] * z
        if k < 3:
            z = z * d
    if a < a_min:
        h = h0 + (h_min - h0) * (a / a_min)
    if a > a_max:
        h = h * (a_max / max(a, a_max))
    return s * h
