"""Where a drawn curve or grid puts its nodes, so that it cannot miss what it shows.

A uniform 1° grid misses a specular peak 0.01° wide (GGX at α = 1e-4). A view seeds
nodes on a geometric ladder at its feature (the mirror direction, θ_m = 0, grazing),
then bisects every interval whose midpoint differs from the straight line drawn between
its ends by more than ``tol`` times the largest value (the error a reader sees on a
linear axis), and puts a node at the located maximum (a vectorised zoom on the bracket
around the largest node; in two dimensions the zoom, then a short Nelder-Mead that
follows a ridge narrower than the zoom's grid). Refinement stops when every checked
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
#: The 2-D peak search's grid (PEAK_NODES_2D² nodes a call; each round that does not
#: move shrinks the box fourfold) and its rounds at most: 60 shrink a 180° box far below
#: PEAK_XTOL, and leave room for rounds that follow a ridge out of the box.
PEAK_NODES_2D = 17
PEAK_ROUNDS_2D = 60
#: The ridge-following simplex after the zoom: its first size as a fraction of the box,
#: and its one-point evaluations at most (~0.4 ms each: 80 ms at most).
RIDGE_SIMPLEX = 1.0 / 64.0
RIDGE_EVALUATIONS = 200
#: ... and it stops when its corners' values agree to this, relative to the peak: the
#: value drawn is then the peak's to far below a pixel, wherever along a ridge it stands.
#: (A bound on the corners' spread alone, 1e-10° as before, took ~160 evaluations a
#: 3-D lobe, the simplex shrinking long after the value had stopped changing.)
RIDGE_FTOL = 1e-12
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
    linear (bilinear) interpolation by more than tol × the largest value. Every value
    computed to judge a round is kept: the refined grid is assembled from it, so each
    point is evaluated once. Returns a, b, fn(a[:, None], b[None, :]) and the report
    of :func:`refine_curve`."""
    a = np.unique(np.asarray(a, dtype=float))
    b = np.unique(np.asarray(b, dtype=float))
    F = fn(a[:, None], b[None, :])
    starts = (a.size, b.size)
    err_max = 0.0
    for _ in range(REFINE_ROUNDS):
        scale = _scale(F) or 1.0
        am, bm = 0.5 * (a[:-1] + a[1:]), 0.5 * (b[:-1] + b[1:])
        rows, cols, cells = fn(am[:, None], b[None, :]), fn(a[:, None], bm[None, :]), fn(am[:, None], bm[None, :])
        e_rows = _gap(F[:-1], rows, F[1:]) / scale
        e_cols = _gap(F[:, :-1], cols, F[:, 1:]) / scale
        e_cell = _gap(0.5 * (F[:-1, :-1] + F[1:, 1:]), cells, 0.5 * (F[1:, :-1] + F[:-1, 1:])) / scale
        err_a = np.maximum(e_rows.max(axis=1, initial=0.0), e_cell.max(axis=1, initial=0.0))
        err_b = np.maximum(e_cols.max(axis=0, initial=0.0), e_cell.max(axis=0, initial=0.0))
        err_max = float(max(err_a.max(initial=0.0), err_b.max(initial=0.0)))
        new_a = _worst(err_a, (err_a > tol) & (am > a[:-1]) & (am < a[1:]), starts[0] + max_added[0] - a.size)
        new_b = _worst(err_b, (err_b > tol) & (bm > b[:-1]) & (bm < b[1:]), starts[1] + max_added[1] - b.size)
        if new_a.size == 0 and new_b.size == 0:
            break
        a, b, F = _merge(a, b, F, am, bm, rows, cols, cells, new_a, new_b)
    a, b, F, located = _insert_peak_2d(fn, a, b, F)
    return a, b, F, {"tolerance": tol, "max_error": err_max, "converged": err_max <= tol,
                     "added": [int(a.size - starts[0]), int(b.size - starts[1])],
                     "located": located}


def _merge(a, b, F, am, bm, rows, cols, cells, new_a, new_b):
    """The grid with the midpoint rows new_a and columns new_b (indices into am, bm)
    inserted, its values taken from the round's evaluations: interleave nodes and
    midpoints into a (2n − 1) grid, then keep every node and the chosen midpoints."""
    A = np.empty(2 * a.size - 1)
    A[0::2], A[1::2] = a, am
    B = np.empty(2 * b.size - 1)
    B[0::2], B[1::2] = b, bm
    keep_a = np.zeros(A.size, dtype=bool)
    keep_a[0::2] = True
    keep_a[1 + 2 * new_a] = True
    keep_b = np.zeros(B.size, dtype=bool)
    keep_b[0::2] = True
    keep_b[1 + 2 * new_b] = True
    full = np.empty((A.size, B.size), dtype=np.result_type(F, rows, cols, cells))
    full[0::2, 0::2], full[1::2, 0::2], full[0::2, 1::2], full[1::2, 1::2] = F, rows, cols, cells
    return A[keep_a], B[keep_b], full[np.ix_(keep_a, keep_b)]


def _gap(lo, mid, hi) -> np.ndarray:
    """|mid − (lo + hi)/2| where all three are finite, else 0 (not refined around)."""
    finite = np.isfinite(lo) & np.isfinite(mid) & np.isfinite(hi)
    return where_valid(finite, [lo, mid, hi], lambda p, m, q: np.abs(m - 0.5 * (p + q)), 0.0)


def _worst(err, bad, room) -> np.ndarray:
    """Indices of the flagged intervals, the worst ``room`` of them if there are more."""
    pick = np.flatnonzero(bad)
    if room <= 0:
        return pick[:0]
    if pick.size > room:
        pick = np.sort(pick[np.argsort(err[pick])[::-1][:room]])
    return pick


def _zoom_max_2d(fn, box, start) -> tuple[float, float, float]:
    """The maximum of fn(x, y) in the box [(x0, x1), (y0, y1)]: a PEAK_NODES_2D² grid
    around the best point so far, one vectorised call a round; the grid shrinks to the
    two cells around its best node when that node is inside it, and only moves when it
    is on an edge (a ridge leading out); until PEAK_XTOL or PEAK_FLAT. (Nelder-Mead
    took ~1 400 one-point calls: 75 % of a 3-D lobe.)"""
    lo, hi = np.array([box[0][0], box[1][0]]), np.array([box[0][1], box[1][1]])
    centre, half = np.asarray(start, dtype=float), 0.5 * (hi - lo)
    xtol = PEAK_XTOL * np.maximum(1.0, np.maximum(np.abs(lo), np.abs(hi)))
    best_xy, best = (float(centre[0]), float(centre[1])), -np.inf
    ramp = np.linspace(-1.0, 1.0, PEAK_NODES_2D)
    for _ in range(PEAK_ROUNDS_2D):
        x = np.clip(centre[0] + half[0] * ramp, lo[0], hi[0])
        y = np.clip(centre[1] + half[1] * ramp, lo[1], hi[1])
        v = fn(x[:, None], y[None, :])
        v = np.where(np.isfinite(v), v, -np.inf)
        i, j = np.unravel_index(int(np.argmax(v)), v.shape)
        # a move only for a gain above rounding: where the function is flat to its last
        # bits (a grazing lobe along φ) the largest node is noise, often on an edge, and
        # chasing it kept the box from shrinking for all PEAK_ROUNDS_2D rounds
        moved = not np.isfinite(best) or v[i, j] > best + PEAK_FLAT * abs(best)
        if moved:
            best_xy, best = (float(x[i]), float(y[j])), float(v[i, j])
        centre = np.array(best_xy)
        edge = [moved and k in (0, PEAK_NODES_2D - 1) and lo[n] < centre[n] < hi[n] for n, k in enumerate((i, j))]
        near = [v[max(i - 1, 0), j], v[min(i + 1, x.size - 1), j], v[i, max(j - 1, 0)], v[i, min(j + 1, y.size - 1)]]
        if not any(edge):
            half = half * 4.0 / (PEAK_NODES_2D - 1)
            if (half <= xtol).all() or not best - min(near) > PEAK_FLAT * abs(best):
                break
    return best_xy[0], best_xy[1], best


def _follow_ridge(fn, box, x: float, y: float, value: float) -> tuple[float, float, float]:
    """Nelder-Mead from the zoom's maximum, its first simplex RIDGE_SIMPLEX of the box:
    a tensor grid can stop on a ridge far narrower than its cells (α = 1e-4 across,
    1 along), which a simplex follows to its end. RIDGE_EVALUATIONS one-point calls at most."""
    def negative(p) -> float:
        v = float(fn(np.array([[p[0]]]), np.array([[p[1]]]))[0, 0])
        return -v if np.isfinite(v) else np.inf
    dx, dy = (RIDGE_SIMPLEX * (hi - lo) for lo, hi in box)
    res = optimize.minimize(negative, [x, y], method="Nelder-Mead", bounds=box,
                            options={"xatol": np.inf, "fatol": RIDGE_FTOL * abs(value), "maxfev": RIDGE_EVALUATIONS,
                                     "initial_simplex": [[x, y], [x + dx, y], [x, y + dy]]})
    if np.isfinite(res.fun) and -res.fun > value:
        return float(res.x[0]), float(res.x[1]), float(-res.fun)
    return x, y, value


def _insert_peak_2d(fn, a, b, F):
    """Add the row and column through the located maximum (searched inside the cells
    around the largest node)."""
    finite = np.isfinite(F)
    if not finite.any():
        return a, b, F, None
    i, j = np.unravel_index(int(np.argmax(np.where(finite, F, -np.inf))), F.shape)
    box = [(a[max(i - 1, 0)], a[min(i + 1, a.size - 1)]), (b[max(j - 1, 0)], b[min(j + 1, b.size - 1)])]
    x, y, value = _zoom_max_2d(fn, box, (a[i], b[j]))
    x, y, value = _follow_ridge(fn, box, x, y, value)
    located = (float(a[i]), float(b[j]), float(F[i, j]))
    if np.isfinite(value) and value > F[i, j]:
        located = (x, y, value)
        if x not in a:
            k = int(np.searchsorted(a, x))
            a, F = np.insert(a, k, x), np.insert(F, k, fn(np.array([[x]]), b[None, :])[0], axis=0)
        if y not in b:
            k = int(np.searchsorted(b, y))
            b, F = np.insert(b, k, y), np.insert(F, k, fn(a[:, None], np.array([[y]]))[:, 0], axis=1)
    return a, b, F, located
