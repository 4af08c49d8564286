"""Kulla-Conty's lobe f_ms = Σ s (1 − Ê(μ_l))(1 − Ê(μ_v)) (Kulla & Conty 2017) at many
pairs, cheaper than app/integrate/compensation.py's for the same values: Ê(μ) at the
model's one α is the table's bicubic spline restricted to that α, a 1-D B-spline in y
(the tensor product contracted along r: the same sum in another order, so equal to
rounding, and checked against the table when built); lobes that share a table and α
(the principled material's three channels) share its evaluations.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
from scipy.interpolate import BSpline

from ..integrate.tables import y_from_mu

#: Largest |Ê_1-D − Ê_table| accepted for the restricted spline, at RESTRICT_CHECK
#: values of μ: both sum the same 16 products B_i(r) B_j(y) c_ij, in another order, so
#: they differ by rounding (~1e-16); anything larger means the table is not the plain
#: tensor-product spline this assumes, and the table's own E is used instead.
RESTRICT_TOL = 1e-12
RESTRICT_CHECK = 65


@lru_cache(maxsize=64)
def one_minus_E(table, alpha: float):
    """μ ↦ 1 − Ê(μ, α): the restricted spline if it agrees with ``table.E`` within
    RESTRICT_TOL, else ``table.E`` itself (the Schlick-basis tables)."""
    def exact(mu):
        return 1.0 - table.E(mu, alpha)
    if table.base is not None or not hasattr(table.spline, "get_coeffs"):
        return exact
    tx, ty = table.spline.get_knots()
    kx, ky = table.spline.degrees
    coeffs = table.spline.get_coeffs().reshape(len(tx) - kx - 1, len(ty) - ky - 1)
    r = np.clip(np.sqrt(alpha), table.r[0], table.r[-1])
    try:
        along_r = BSpline.design_matrix(np.array([r]), tx, kx).toarray()[0]
    except ValueError:           # r outside the knots: not the spline assumed here
        return exact
    spline_y = BSpline(ty, along_r @ coeffs, ky)
    alpha_y = np.clip(alpha, table.r[0] ** 2, 1.0)

    def fast(mu):
        return 1.0 - np.clip(spline_y(y_from_mu(np.clip(mu, 0.0, 1.0), alpha_y)), 0.0, 1.0)

    mu = np.linspace(0.0, 1.0, RESTRICT_CHECK)
    return fast if np.max(np.abs(fast(mu) - exact(mu))) <= RESTRICT_TOL else exact


def f_ms_rgb(channels, mu_l, mu_v, pixel=None) -> np.ndarray:
    """(..., len(channels)): each channel's KullaConty lobe at (μ_l, μ_v), 1 − Ê evaluated
    once per (table, α) the channels' lobes use; with ``pixel``, μ_v is given once per
    pixel and pair i has μ_v[pixel[i]] (the renderer's samples)."""
    if pixel is None:
        mu_l, mu_v = np.broadcast_arrays(np.asarray(mu_l, dtype=float), np.asarray(mu_v, dtype=float))
    products: dict = {}
    out = np.zeros(mu_l.shape + (len(channels),))
    for c, ms in enumerate(channels):
        for term in ms.lobes:
            if term.scale:
                key = (term.table, term.alpha)
                if key not in products:
                    e = one_minus_E(*key)
                    products[key] = e(mu_l) * (e(mu_v) if pixel is None else e(mu_v)[pixel])
                out[..., c] += term.scale * products[key]
    return out
