"""The tabulated μΛ of ``smith_table.py`` as floats and a scalar formula.

For an NDF whose Λ has no closed form (and for ``smith_numeric``), ``smith_table``
interpolates h = μΛ/s by a cubic per interval of a uniform grid in ln a (a = μ/s).
:func:`table_params` packs that :class:`~.smith_table.LambdaTable` into one float array
and :func:`tabulated_mu_Lambda_scalar` evaluates it for one point with the same
interval, the same Horner form and the same end laws as ``LambdaTable.h``, so a
compiled loop and the numpy path agree to rounding.
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np

from .scalar import scalar
from .smith_table import LambdaTable, lambda_table

#: Floats before the coefficients: h(0), h(a_min), a_min, a_max, x₀, dx, intervals.
HEADER = 7


@lru_cache(maxsize=64)
def _packed(ndf_class, alpha: float, shape: tuple) -> np.ndarray:
    table: LambdaTable = lambda_table(ndf_class(alpha, None, **dict(shape)))
    c = table.coefficients
    out = np.concatenate([[table.h0, table.h_min, table.a_min, table.a_max, table.x0,
                           table.dx, c.shape[1]], c.ravel()])
    out.flags.writeable = False
    return out


def table_params(ndf) -> np.ndarray:
    """The table of ``ndf``'s shape (smith_table.lambda_table), packed (cached by what the
    table depends on: the NDF class, its shape and α where not shape-invariant)."""
    shape = tuple((p.name, getattr(ndf, p.name)) for p in ndf.shape_params)
    return _packed(type(ndf), ndf.alpha_x if not ndf.shape_invariant else 1.0, shape)


@scalar
def tabulated_mu_Lambda_scalar(mu, s, p, at):
    """μΛ at (μ, s) from the table packed in ``p`` from index ``at``."""
    if not s > 0.0:
        return 0.0
    h0, h_min, a_min, a_max, x0, dx = p[at], p[at + 1], p[at + 2], p[at + 3], p[at + 4], p[at + 5]
    n = int(p[at + 6])
    c = at + HEADER                  # coefficient k of interval i at c + k n + i
    a = mu / s
    x = math.log(min(max(a, a_min), a_max))
    i = int(min(max(math.floor((x - x0) / dx), 0.0), n - 1.0))
    t = x - (x0 + i * dx)
    h = ((p[c + i] * t + p[c + n + i]) * t + p[c + 2 * n + i]) * t + p[c + 3 * n + i]
    h = h0 + (h_min - h0) * (a / a_min) if a < a_min else h
    return s * (h * (a_max / max(a, a_max)) if a > a_max else h)
