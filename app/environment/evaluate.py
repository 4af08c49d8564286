"""f at the renderer's samples: pairs (l, v) with both directions upper, v one per pixel.

The same f as ``brdf.evaluate``, cheaper for this case. A grey model: its specular lobe(s)
from the compiled loop (app/kernels: the loop exists for the microfacet part even when a
numpy diffuse model such as Burley sends the whole model to numpy), the diffuse term
beside it, and the Kulla-Conty lobe f_ms = s (1 − Ê(μ_l))(1 − Ê(μ_v)) (Kulla & Conty 2017)
with 1 − Ê(μ_v) once per pixel and Ê(μ_l) from the table's spline restricted to the
model's α (app/principled/compensation.py); the principled material's per-channel
Kulla-Conty lobes likewise. The principled material and the measured materials give
three channels; a grey f comes back as (M,), not repeated.
"""
from __future__ import annotations

from dataclasses import replace
from functools import lru_cache

import numpy as np

from .. import kernels
from ..physics.brdf import CompensatedBRDF
from ..principled.compensation import f_ms_rgb, one_minus_E


def f_samples(brdf, l, v, pixel) -> np.ndarray:
    """f for l (M, 3) and v[pixel], v (P, 3) per pixel, every direction upper: (M,) for
    a grey model, (M, 3) per channel for the principled and the measured materials."""
    m = getattr(brdf, "material", None)
    if m is not None:
        if m.options.get("principled_multiscatter") != "kulla_conty" or brdf.lobe not in ("all", "specular"):
            return m.f_rgb(l, v[pixel], brdf.lobe)
        return (_single_scattering(m).f_rgb(l, v[pixel], brdf.lobe)
                + f_ms_rgb(m.multiscatter(), l[:, 2], v[:, 2], pixel))
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


@lru_cache(maxsize=16)
def _single_scattering(material):
    """The principled material without its Kulla-Conty lobes (added per pixel above)."""
    return replace(material, options={**material.options, "principled_multiscatter": "none"})


def prepare(brdf) -> None:
    """Compile (or load) the loops :func:`f_samples` uses, in this thread (benchmarks,
    tests); the server queues them in the background and answers by numpy until then."""
    if getattr(brdf, "material", None) is not None:
        from ..physics.fresnel import FRESNELS
        kernels.compile_now(brdf.material.specular_brdf(FRESNELS["none"]()), "f")
        return
    single = brdf.single() if isinstance(brdf, CompensatedBRDF) else brdf
    kernels.compile_now(replace(single, kd=0.0, diffuse=None), "f")


def multiscatter(ms, mu_l, mu_v, pixel) -> np.ndarray:
    """f_ms(μ_l, μ_v[pixel]) of a Kulla-Conty lobe: Σ_lobes s (1 − Ê(μ_l))(1 − Ê(μ_v))."""
    if getattr(ms, "lobes", None) is None:
        return ms(mu_l, mu_v[pixel])
    out = np.zeros(mu_l.shape)
    for term in ms.lobes:
        if term.scale:
            e = one_minus_E(term.table, term.alpha)
            out += term.scale * e(mu_l) * e(mu_v)[pixel]
    return out
