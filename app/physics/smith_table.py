"""μΛ from the general Smith integral, tabulated once per NDF shape and interpolated.

For an NDF whose Λ has no closed form (GTR, exponential power), μΛ/s is a function of
a = μ/s alone once the shape is fixed (for GTR the shape includes α, since it is not
shape-invariant). It is tabulated on TABLE_NODES points uniform in t = a/(1 + a) ∈ [0, 1]
with the reference integral (smith_integral.py) and interpolated linearly. Measured
against the direct integral: |ΔμΛ| ≤ 2e-8·s (tests/physics/test_smith_integral.py), far
inside the 1e-5 that ``smith`` must meet against ``smith_numeric``.

Tables are cached (bounded): building one costs TABLE_NODES × ORDER integrand
evaluations, about 20 ms.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

from .numeric import where_valid
from .smith_integral import mu_Lambda_numeric

TABLE_NODES = 2049
CACHE_SIZE = 64


@lru_cache(maxsize=CACHE_SIZE)
def _table(ndf_class, alpha: float, shape: tuple) -> np.ndarray:
    ndf = ndf_class(alpha, None, **dict(shape))
    t = np.linspace(0.0, 1.0, TABLE_NODES)
    # Unit directions with s = α sinθ and a = μ/s = t/(1 − t) in the stretched frame:
    # μ = a·s; take s = α·sinθ with μ² + sin²θ = 1.
    a = where_valid(t < 1, [t], lambda x: x / (1.0 - x), np.inf)
    # sinθ from a: μ/(α sinθ) = a  →  tanθ = 1/(α a)
    sin_t = where_valid(np.isfinite(a), [a], lambda x: 1.0 / np.sqrt(1.0 + (alpha * x) ** 2), 0.0)
    mu = np.sqrt(1.0 - sin_t * sin_t)
    w = np.stack([sin_t, np.zeros_like(t), mu], axis=-1)
    s = alpha * sin_t
    h = where_valid(s > 0, [mu_Lambda_numeric(ndf, w), s], lambda ml, ss: ml / ss, 0.0)
    h.flags.writeable = False
    return h


def mu_Lambda_tabulated(ndf, mu, s) -> np.ndarray:
    """μΛ for ``ndf`` (an isotropic slope-space NDF or a shape-invariant one) at (μ, s)."""
    shape = tuple((p.name, getattr(ndf, p.name)) for p in ndf.shape_params)
    alpha = ndf.alpha_x if not ndf.shape_invariant else 1.0
    h = _table(type(ndf), alpha, shape)
    t = where_valid(s > 0, [mu, s], lambda m, ss: m / (m + ss), 1.0)
    return s * np.interp(t, np.linspace(0.0, 1.0, TABLE_NODES), h)
