"""Independent references for the tests: brute-force integration of definitions.

Nothing here uses the slope-space machinery of ``app.integrate``: the albedo reference
integrates f(l, v)(n·l) over l directly, in (μ_l, φ_l), by adaptive cubature.
"""
from __future__ import annotations

import numpy as np


def _gauss(n):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (x + 1), 0.5 * w


def adaptive_cubature_2d(func, x0, x1, y0, y1, tol=1e-7, max_rounds=40, min_split=3,
                         max_cells=20000):
    """∫∫ func(x, y) over a rectangle, adaptively.

    Each cell is integrated by 6×6 and 12×12 Gauss rules; cells whose two results differ
    by more than tol × (cell area / total area) are split in four. The first
    ``min_split`` rounds split everything so that a narrow peak is not missed. When more
    than ``max_cells`` cells would need splitting, the worst ``max_cells`` are split and
    the rest accepted, their differences added to the error estimate (so the error
    stays honest when the budget, not the tolerance, ends the refinement).
    Returns (value, error estimate, number of evaluations).
    """
    xa, wa = _gauss(6)
    xb, wb = _gauss(12)
    cells = np.array([[x0, x1, y0, y1]], dtype=float)
    total_area = (x1 - x0) * (y1 - y0)
    value, error, evals = 0.0, 0.0, 0

    def rule(cells, xs, ws):
        cx0, cx1, cy0, cy1 = (cells[:, i][:, None, None] for i in range(4))
        X = cx0 + (cx1 - cx0) * xs[None, :, None]
        Y = cy0 + (cy1 - cy0) * xs[None, None, :]
        W = ws[None, :, None] * ws[None, None, :] * (cx1 - cx0) * (cy1 - cy0)
        return np.sum(func(X, Y) * W, axis=(1, 2))

    for round_ in range(max_rounds):
        ia, ib = rule(cells, xa, wa), rule(cells, xb, wb)
        evals += cells.shape[0] * (36 + 144)
        diff = np.abs(ia - ib)
        area = (cells[:, 1] - cells[:, 0]) * (cells[:, 3] - cells[:, 2])
        ok = diff <= tol * area / total_area if round_ >= min_split else np.zeros(len(cells), bool)
        if (~ok).sum() > max_cells // 4:
            worst = np.argsort(diff * ~ok)[::-1][: max_cells // 4]
            ok = np.ones(len(cells), bool)
            ok[worst] = False
        value += ib[ok].sum()
        error += diff[ok].sum()
        bad = cells[~ok]
        if bad.size == 0:
            return value, error, evals
        xm = 0.5 * (bad[:, 0] + bad[:, 1])
        ym = 0.5 * (bad[:, 2] + bad[:, 3])
        cells = np.concatenate([
            np.stack([bad[:, 0], xm, bad[:, 2], ym], 1), np.stack([xm, bad[:, 1], bad[:, 2], ym], 1),
            np.stack([bad[:, 0], xm, ym, bad[:, 3]], 1), np.stack([xm, bad[:, 1], ym, bad[:, 3]], 1)])
    value += ib.sum()
    error += diff.sum()
    return value, error, evals


def albedo_brute_force(brdf, mu_v, phi_v=0.0, tol=1e-7):
    """E(μ_v) = ∫ f(l, v) μ_l dμ_l dφ_l over the upper hemisphere, adaptively."""
    st = np.sqrt(max(0.0, 1.0 - mu_v * mu_v))
    v = np.array([st * np.cos(phi_v), st * np.sin(phi_v), mu_v])

    def integrand(mu_l, phi_l):
        mu_l, phi_l = np.broadcast_arrays(mu_l, phi_l)
        s = np.sqrt(np.maximum(0.0, 1.0 - mu_l * mu_l))
        l = np.stack([s * np.cos(phi_l), s * np.sin(phi_l), mu_l], axis=-1)
        return brdf.f(l, np.broadcast_to(v, l.shape)) * mu_l

    # φ_l centred on the mirror azimuth, so the peak is not cut by the period.
    c = phi_v + np.pi
    return adaptive_cubature_2d(integrand, 0.0, 1.0, c - np.pi, c + np.pi, tol=tol)
