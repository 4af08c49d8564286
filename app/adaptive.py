"""Where a drawn curve or grid puts its nodes, so that it cannot miss what it shows.

A uniform 1° grid misses a specular peak 0.01° wide (GGX at α = 1e-4). A view seeds
nodes on a geometric ladder at its feature (the mirror direction, θ_m = 0, grazing),
then bisects every interval whose midpoint differs from the straight line drawn between
its ends by more than ``tol`` times the largest value (the error a reader sees on a
linear axis), and puts a node at the located maximum (a vectorised zoom on the bracket
around the largest node, or Nelder-Mead in two dimensions, started at the largest node). Refinement stops when every checked
midpoint is within tolerance or after ``max_added`` nodes; the report says which.
Non-finite values (a divergence at double grazing) are not refined around.
"""
from __future__ import annotations

from typing import Callable

import numpy as np
from scipy import optimize

from .physics.numeric import where_valid

#: Allowed gap between a drawn segment and the function at its midpoint, relative to the
#: largest value drawn: 0.5 % is below a pixel on a 200-pixel-high plot.
REFINE_TOL = 0.005
#: Bisection rounds at most (each at most doubles a flagged interval's nodes; 40 rounds
#: split 180° to 1.6e-10°, far below any feature of α ≥ 1e-4).
REFINE_ROUNDS = 40
#: The smallest step of a ladder, as a fraction of the feature width.
LADDER_FIRST = 0.125
#: Nodes of each round of the 1-D peak search: one vectorised call of the function per
#: round, the bracket shrunk (PEAK_NODES − 1)/2 = 16 times. (Brent's method called it
#: ~55 times one point at a time: 90 % of a curve request's time.)
PEAK_NODES = 33
#: The search stops when the bracket is narrower than this, relative to max(1, |x|), as
#: Brent's xatol did before it ...
PEAK_XTOL = 1e-12
#: ... or when the best node's neighbours (the next bracket's ends) are within this of
#: it, relative: a smooth peak is then flat across the bracket to the last bits of a
#: double, and no node inside can be higher by more.
PEAK_FLAT = 1e-15


def ladder(centre: float, width: float, lo: float, hi: float) -> np.ndarray:
    """Nodes centre ± width·2^k (k from log2(LADDER_FIRST) up) within [lo, hi]."""
    steps = width * LADDER_FIRST * 2.0 ** np.arange(0, 64)
    steps = steps[steps < 2 * (hi - lo)]
    nodes = np.concatenate([[centre], centre - steps, centre + steps])
    return nodes[(nodes >= lo) & (nodes <= hi)]


def refine_curve(fn: Callable, x, tol: float = REFINE_TOL, max_added: int = 256, locate: bool = True):
    """Nodes x (sorted, unique), values fn(x) and a report {tolerance, max_error,
    converged, added, located}: max_error is the largest midpoint gap of the last round
    relative to the largest finite value, located the maximum (x*, fn(x*)), searched
    for and drawn as a node only when ``locate``."""
    x = np.unique(np.asarray(x, dtype=float))
    y = fn(x)
    start = x.size
    err_max = 0.0
    for _ in range(REFINE_ROUNDS):
        scale = _scale(y)
        mid = 0.5 * (x[:-1] + x[1:])
        y_mid = fn(mid)
        err = _gap(y[:-1], y_mid, y[1:])
        bad = (err > tol * scale) & (mid > x[:-1]) & (mid < x[1:])   # not below float spacing
        err_max = float(err.max() / scale) if err.size and scale > 0 else 0.0
        room = start + max_added - x.size
        if not bad.any() or room <= 0:
            break
        pick = np.flatnonzero(bad)
        if pick.size > room:
            pick = pick[np.argsort(err[pick])[::-1][:room]]
        x, y = _insert(x, y, mid[pick], y_mid[pick])
    x, y, located = _insert_peak_1d(fn, x, y) if locate else (x, y, None)
    return x, y, {"tolerance": tol, "max_error": err_max, "converged": err_max <= tol,
                  "added": int(x.size - start), "located": located}


def _scale(y) -> float:
    finite = y[np.isfinite(y)]
    return float(np.abs(finite).max()) if finite.size else 0.0


def _insert(x, y, x_new, y_new):
    order = np.argsort(np.concatenate([x, x_new]), kind="stable")
    return np.concatenate([x, x_new])[order], np.concatenate([y, y_new])[order]


def _insert_peak_1d(fn, x, y):
    """Add the located maximum between the largest node's neighbours as a node."""
    if not np.isfinite(y).any():
        return x, y, None
    k = int(np.argmax(np.where(np.isfinite(y), y, -np.inf)))
    lo, hi = x[max(k - 1, 0)], x[min(k + 1, x.size - 1)]
    located = (float(x[k]), float(y[k]))
    if hi > lo:
        t, value = _zoom_max(fn, lo, hi)
        if value > y[k]:
            located = (t, value)
            if t not in x:
                x, y = _insert(x, y, np.array([t]), np.array([value]))
    return x, y, located


def _zoom_max(fn, lo: float, hi: float) -> tuple[float, float]:
    """The maximum of fn on [lo, hi]: PEAK_NODES nodes across the bracket, then the two
    intervals around the best, until PEAK_XTOL or PEAK_FLAT (non-finite values lose)."""
    xtol = PEAK_XTOL * max(1.0, abs(lo), abs(hi))
    best_t, best = lo, -np.inf
    while True:
        t = np.linspace(lo, hi, PEAK_NODES)
        v = fn(t)
        v = np.where(np.isfinite(v), v, -np.inf)
        k = int(np.argmax(v))
        if v[k] > best:
            best_t, best = float(t[k]), float(v[k])
        a, b = max(k - 1, 0), min(k + 1, t.size - 1)
        lo, hi = t[a], t[b]
        if hi - lo <= xtol or not best - min(v[a], v[b]) > PEAK_FLAT * abs(best):
            return best_t, best


def _negative(value) -> float:
    """−value for a minimiser; +inf where the function is not finite (no such point is
    the maximum drawn)."""
    value = float(value)
    return -value if np.isfinite(value) else np.inf


def peak(values, located, name: str, *where: str) -> dict:
    """The largest drawn value against the located maximum ``(position..., value)`` of
    the refinement, with their relative gap; ``where`` names the position's coordinates."""
    values = np.asarray(values, dtype=float)
    finite = values[np.isfinite(values)]
    if located is None or finite.size == 0:
        return {f"{name}_drawn_max": None, f"{name}_true_max": None,
                **{k: None for k in where}, "relative_error": None}
    drawn = float(finite.max())
    true = max(drawn, located[-1])
    return {f"{name}_drawn_max": drawn, f"{name}_true_max": true,
            **{k: float(v) for k, v in zip(where, located[:-1])},
            "relative_error": (true - drawn) / true if true > 0 else 0.0}


def refine_grid(fn: Callable, a, b, tol: float = REFINE_TOL, max_added=(128, 128)):
    """A tensor grid a × b refined along both axes: a row (column) interval is bisected
    where the function at its midpoints, or at the centres of its cells, is off the
    linear (bilinear) interpolation by more than tol × the largest value. Returns a, b,
    fn(a[:, None], b[None, :]) and the report of :func:`refine_curve`."""
    a = np.unique(np.asarray(a, dtype=float))
    b = np.unique(np.asarray(b, dtype=float))
    F = fn(a[:, None], b[None, :])
    starts = (a.size, b.size)
    err_max = 0.0
    for _ in range(REFINE_ROUNDS):
        scale = _scale(F) or 1.0
        am, bm = 0.5 * (a[:-1] + a[1:]), 0.5 * (b[:-1] + b[1:])
        e_rows = _gap(F[:-1], fn(am[:, None], b[None, :]), F[1:]) / scale
        e_cols = _gap(F[:, :-1], fn(a[:, None], bm[None, :]), F[:, 1:]) / scale
        e_cell = _gap(0.5 * (F[:-1, :-1] + F[1:, 1:]), fn(am[:, None], bm[None, :]),
                      0.5 * (F[1:, :-1] + F[:-1, 1:])) / scale
        err_a = np.maximum(e_rows.max(axis=1, initial=0.0), e_cell.max(axis=1, initial=0.0))
        err_b = np.maximum(e_cols.max(axis=0, initial=0.0), e_cell.max(axis=0, initial=0.0))
        err_max = float(max(err_a.max(initial=0.0), err_b.max(initial=0.0)))
        new_a = _worst(am, err_a, (err_a > tol) & (am > a[:-1]) & (am < a[1:]),
                       starts[0] + max_added[0] - a.size)
        new_b = _worst(bm, err_b, (err_b > tol) & (bm > b[:-1]) & (bm < b[1:]),
                       starts[1] + max_added[1] - b.size)
        if new_a.size == 0 and new_b.size == 0:
            break
        a, b = np.union1d(a, new_a), np.union1d(b, new_b)
        F = fn(a[:, None], b[None, :])
    a, b, F, located = _insert_peak_2d(fn, a, b, F)
    return a, b, F, {"tolerance": tol, "max_error": err_max, "converged": err_max <= tol,
                     "added": [int(a.size - starts[0]), int(b.size - starts[1])],
                     "located": located}


def _gap(lo, mid, hi) -> np.ndarray:
    """|mid − (lo + hi)/2| where all three are finite, else 0 (not refined around)."""
    finite = np.isfinite(lo) & np.isfinite(mid) & np.isfinite(hi)
    return where_valid(finite, [lo, mid, hi], lambda p, m, q: np.abs(m - 0.5 * (p + q)), 0.0)


def _worst(mid, err, bad, room) -> np.ndarray:
    pick = np.flatnonzero(bad)
    if room <= 0:
        return mid[:0]
    if pick.size > room:
        pick = pick[np.argsort(err[pick])[::-1][:room]]
    return mid[pick]


def _insert_peak_2d(fn, a, b, F):
    """Add the row and column through the located maximum (Nelder-Mead from the
    largest node, kept inside the cells around it)."""
    finite = np.isfinite(F)
    if not finite.any():
        return a, b, F, None
    i, j = np.unravel_index(int(np.argmax(np.where(finite, F, -np.inf))), F.shape)
    box = [(a[max(i - 1, 0)], a[min(i + 1, a.size - 1)]), (b[max(j - 1, 0)], b[min(j + 1, b.size - 1)])]
    res = optimize.minimize(lambda p: _negative(fn(np.array([[p[0]]]), np.array([[p[1]]]))[0, 0]),
                            [a[i], b[j]], method="Nelder-Mead", bounds=box,
                            options={"xatol": 1e-10, "fatol": 0.0, "maxiter": 400})
    located = (float(a[i]), float(b[j]), float(F[i, j]))
    if np.isfinite(res.fun) and -res.fun > F[i, j]:
        located = (float(res.x[0]), float(res.x[1]), float(-res.fun))
        a, b = np.union1d(a, [res.x[0]]), np.union1d(b, [res.x[1]])
        F = fn(a[:, None], b[None, :])
    return a, b, F, located
