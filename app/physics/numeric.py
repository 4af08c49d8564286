"""Evaluate a formula only where it is valid (the idea of scipy's ``_lazywhere``).

Every special case in the physics layer goes through :func:`where_valid`, so a formula is
never evaluated on inputs where it would divide by zero or overflow, and no NaN is
cleaned up after the fact.
"""
from __future__ import annotations

import math
from typing import Callable

import numpy as np

from .scalar import scalar


def where_valid(cond, arrays, formula: Callable, fill) -> np.ndarray:
    """``formula(*arrays)`` where ``cond`` holds, ``fill`` (scalar or array) elsewhere.

    ``arrays`` are broadcast against ``cond``; ``formula`` only ever sees the entries
    where ``cond`` is true, so it may assume its preconditions.
    """
    cond, *args = np.broadcast_arrays(np.asarray(cond, dtype=bool),
                                      *[np.asarray(a, dtype=float) for a in arrays])
    if cond.all():
        return np.array(np.broadcast_to(formula(*args), cond.shape), dtype=float)
    out = np.array(np.broadcast_to(np.asarray(fill, dtype=float), cond.shape))
    if cond.any():
        out[cond] = formula(*[a[cond] for a in args])
    return out


def on_mask(mask, func: Callable, vectors, fill: float = 0.0) -> np.ndarray:
    """``func(vectors)`` for the direction arrays (..., 3) where ``mask`` (...) holds.

    The vector counterpart of :func:`where_valid`, for formulas that take whole
    directions (an NDF at a half vector that may not exist).
    """
    mask = np.asarray(mask, dtype=bool)
    vectors = np.asarray(vectors, dtype=float)
    mask = np.broadcast_to(mask, vectors.shape[:-1])
    if mask.all():
        return np.asarray(func(vectors), dtype=float)
    out = np.full(mask.shape, fill, dtype=float)
    if mask.any():
        out[mask] = func(vectors[mask])
    return out


# Below this |y| the series of expm1(y)/y and log1p(y)/y are exact to double precision
# (the next term is y²/6 ≈ 1e-17 relative).
SERIES_CUTOFF = 1e-8


def expm1_ratio(y) -> np.ndarray:
    """E(y) = (e^y − 1)/y, continuous through its removable singularity E(0) = 1."""
    y = np.asarray(y, dtype=float)
    small = np.abs(y) < SERIES_CUTOFF
    return np.where(small, 1.0 + 0.5 * y, where_valid(~small, [y], lambda x: np.expm1(x) / x, 1.0))


def log1p_ratio(y) -> np.ndarray:
    """log(1 + y)/y, continuous through y = 0 (value 1); y > −1."""
    y = np.asarray(y, dtype=float)
    small = np.abs(y) < SERIES_CUTOFF
    return np.where(small, 1.0 - 0.5 * y, where_valid(~small, [y], lambda x: np.log1p(x) / x, 1.0))


@scalar
def expm1_ratio_scalar(y):
    """:func:`expm1_ratio` for one value."""
    return 1.0 + 0.5 * y if abs(y) < SERIES_CUTOFF else math.expm1(y) / y


@scalar
def log1p_ratio_scalar(y):
    """:func:`log1p_ratio` for one value."""
    return 1.0 - 0.5 * y if abs(y) < SERIES_CUTOFF else math.log1p(y) / y
