"""f at the renderer's samples: pairs (l, v) with both directions upper, v one per pixel.

The same f as ``brdf.evaluate``, cheaper for this case. A grey model: its specular lobe(s)
from the compiled loop (app/kernels: the loop exists for the microfacet part even when a
numpy diffuse model such as Burley sends the whole model to numpy), the diffuse term
beside it, and the Kulla-Conty lobe f_ms = s (1 − Ê(μ_l))(1 − Ê(μ_v)) (Kulla & Conty 2017)
with 1 − Ê(μ_v) once per pixel and Ê(μ_l) from the table's bicubic spline restricted to
the model's α, a 1-D B-spline in y (the tensor product contracted along r: the same sum,
other rounding; checked against the table when built). The principled material and the
measured materials give three channels; a grey f comes back as (M,), not repeated.
"""
from __future__ import annotations

from dataclasses import replace
from functools import lru_cache

import numpy as np
from scipy.interpolate import BSpline

from .. import kernels
from ..integrate.tables import y_from_mu
from ..physics.brdf import CompensatedBRDF

#: Largest |Ê_1-D − Ê_table| accepted for the restricted spline, at RESTRICT_CHECK
#: values of μ: both sum the same 16 products B_i(r) B_j(y) c_ij, in another order, so
#: they differ by rounding (~1e-16); anything larger means the table is not the plain
#: tensor-product spline this assumes, and the table's own E is used instead.
RESTRICT_TOL = 1e-12
RESTRICT_CHECK = 65


def f_samples(brdf, l, v, pixel) -> np.ndarray:
    """f for l (M, 3) and v[pixel], v (P, 3) per pixel, every direction upper: (M,) for
    a grey model, (M, 3) per channel for the principled and the measured materials."""
    if getattr(brdf, "material", None) is not None:
        return brdf.material.f_rgb(l, v[pixel], brdf.lobe)
    if getattr(brdf.fresnel, "channels", None) is not None:      # material=<measured metal>
        from ..materials import evaluate_rgb
        return evaluate_rgb(brdf, l, v[pixel])["f_rgb"]
    single = brdf.single() if isinstance(brdf, CompensatedBRDF) else brdf
    vp = v[pixel]
    f = kernels.f(replace(single, kd=0.0, diffuse=None), l, vp)
    if single.diffuse is not None:
        f = f + single.diffuse.f(single.kd, l[:, 2], vp[:, 2], np.einsum("mi,mi->m", l, vp))
    elif single.kd:
        f = f + single.kd / np.pi
    if isinstance(brdf, CompensatedBRDF) and brdf.multiscatter is not None:
        f = f + multiscatter(brdf.multiscatter, l[:, 2], v[:, 2], pixel)
    return f


def prepare(brdf) -> None:
    """Compile (or load) the loops :func:`f_samples` uses, in this thread (benchmarks,
    tests); the server queues them in the background and answers by numpy until then."""
    if getattr(brdf, "material", None) is not None:
        from ..physics.fresnel import FRESNELS
        kernels.compile_now(brdf.material.specular_brdf(FRESNELS["none"]()))
        return
    single = brdf.single() if isinstance(brdf, CompensatedBRDF) else brdf
    kernels.compile_now(replace(single, kd=0.0, diffuse=None))


def multiscatter(ms, mu_l, mu_v, pixel) -> np.ndarray:
    """f_ms(μ_l, μ_v[pixel]) of a Kulla-Conty lobe: Σ_lobes s (1 − Ê(μ_l))(1 − Ê(μ_v))."""
    if getattr(ms, "lobes", None) is None:
        return ms(mu_l, mu_v[pixel])
    out = np.zeros(mu_l.shape)
    for term in ms.lobes:
        if term.scale:
            one_minus_E = _one_minus_E(term)
            out += term.scale * one_minus_E(mu_l) * one_minus_E(mu_v)[pixel]
    return out


@lru_cache(maxsize=64)
def _one_minus_E(term):
    """μ ↦ 1 − Ê(μ, α) of one lobe term: the restricted spline if it agrees with the
    table within RESTRICT_TOL, else the table's own (the Schlick-basis tables)."""
    table = term.table
    if table.base is not None or not hasattr(table.spline, "get_coeffs"):
        return term.one_minus_E
    tx, ty = table.spline.get_knots()
    kx, ky = table.spline.degrees
    coeffs = table.spline.get_coeffs().reshape(len(tx) - kx - 1, len(ty) - ky - 1)
    r = np.clip(np.sqrt(term.alpha), table.r[0], table.r[-1])
    try:
        along_r = BSpline.design_matrix(np.array([r]), tx, kx).toarray()[0]
    except ValueError:           # r outside the knots: not the spline assumed here
        return term.one_minus_E
    spline_y = BSpline(ty, along_r @ coeffs, ky)
    alpha = np.clip(term.alpha, table.r[0] ** 2, 1.0)

    def fast(mu):
        y = y_from_mu(np.clip(mu, 0.0, 1.0), alpha)
        return 1.0 - np.clip(spline_y(y), 0.0, 1.0)

    mu = np.linspace(0.0, 1.0, RESTRICT_CHECK)
    return fast if np.max(np.abs(fast(mu) - term.one_minus_E(mu))) <= RESTRICT_TOL else term.one_minus_E
