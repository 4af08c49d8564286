"""f(l, v) in float32: the model's compiled loop in single precision, on explicit request only.

Float64 is the default everywhere (the API, the figures, the tables, the reference numpy
path); this loop serves a caller that trades accuracy for speed and asks for it
(POST /api/v1/eval with ``"precision": "float32"``, bench/throughput.py). It is generated
from the same single spelling of each formula as the float64 loops (compose.float32_source:
each Formula's float32 translation, compose.PAIR and F_LOOP with their numbers typed
float32): 8 lanes of AVX2 a step instead of 4, and single-precision division and square
root, ~2x the float64 loop's pairs a second.

A model has a float32 loop when every formula its f loop calls is a Formula (not written
by hand) and its error is measured within the stated bound: GGX with the smith, karis,
schlick_direct and schlick_ibl maskings, every G2 form and λ(φ), every Fresnel and
diffuse model. Not: Beckmann and Blinn-Phong (their formulas translate, but float32
breaks there: NOT_FLOAT32), GTR,
Student-t and exponential power with smith (their Smith μΛ reads a table or scipy's
special functions, written by hand), the smith_numeric masking (a table of the Smith
integral), compensated models (their multiple-scattering term is a float64 table), the
principled BRDF (numpy only); :func:`unsupported` says which and why.

Its error against float64 is :func:`rel_error_bound` (measured: REL_ERROR_K says how);
float32 is offered for the NDFs whose error that bound holds (FLOAT32_NDFS: GGX), not
where float32 breaks (NOT_FLOAT32: Beckmann's exp tails, Blinn-Phong's pow).
"""
from __future__ import annotations

import logging
import threading
from dataclasses import replace
from pathlib import Path

import numpy as np

from ..physics.brdf import CompensatedBRDF, blend_lobes
from . import compose
from .compiler import CLIENT
from .compose import Components, Float32Unsupported
from .kernel import PARALLEL_MIN
from .kernel32 import Kernel32

#: Float32 ε (2⁻²⁴: half a unit in the last place of 1).
EPS32 = 2.0 ** -24

#: The float32 loop's stated error against the float64 numpy path (BRDF.evaluate), pair
#: by pair: |f32 − f64| ≤ REL_ERROR_K / (α_min (μ_l + μ_v)) · f64, α_min = min(α_x, α_y).
#: Why that form: the half vector's x, y near the specular peak are sums l_x + v_x that
#: cancel, so they carry an absolute error of ~ε (float32 directions: Mitsuba's too), and
#: D reads them divided by α, while the half vector's norm falls with μ_l + μ_v where the
#: two directions graze on opposite sides (the grazing mirror pair): a relative error of
#: ~ε/(α (μ_l + μ_v)) in D. Every other float32 operation adds a few ε, far below that.
#: Measured (app.kernels.float32.measure, 2026-12-08 on this machine): the largest
#: rel · α_min · (μ_l + μ_v) was 398 ε (2.4e-5) over the five GGX classes of
#: tests/kernels/test_float32.py's FLOAT32_CASES (every masking that applies to GGX, all
#: five G2 forms with both λ(φ), the four Fresnel and five diffuse models), α ∈ {1, 0.3,
#: 0.1, 0.01, 1e-3, 1e-4} isotropic and α_y = α/2, ρ_d ∈ {0, 0.5}, 10⁵ pairs each (half
#: uniform with cosines down to 1e-7 and 2 % on the horizon exactly, half around the
#: specular peak); stated with 1.3x margin: 512 ε. So at α = 0.3 and μ_l + μ_v ≥ 1 the
#: bound is 1e-4 (measured there: ≤ 2e-6); at α = 1e-4 and normal incidence 0.15. Pairs
#: with both directions on the horizon (μ_l + μ_v = 0) have no bound (measured ≤ 6e-6);
#: where f64 is 0 or ∞ the float32 loop gives the same.
REL_ERROR_K = 512 * EPS32

#: The NDFs whose float32 error is bounded as above (their formulas all translate to
#: float32; these are the ones measured within the bound). The others, with why:
FLOAT32_NDFS = ("ggx",)
NOT_FLOAT32 = {
    "beckmann": "Beckmann's D is exp(−tan²θ/α²)/…: the exponential leaves float32's range "
                "(1.2e-38) where float64 still holds it (1e-308), and the argument's rounding "
                "is multiplied by tan²θ/α² (measured: relative error 3.5e-2 at α = 1e-4 "
                "away from grazing, 4.8 at μ = 1e-3)",
    "blinn_phong": "Blinn-Phong's D is cos θ_h^(2/α² − 2): float32's rounding of cos θ_h "
                   "is multiplied by the exponent (measured: relative error 0.37 at α = 1e-3, "
                   "1.5e11 at α = 1e-4)",
}


def rel_error_bound(alpha_x: float, alpha_y: float, mu_sum) -> float | np.ndarray:
    """The stated bound on |f32 − f64| / f64 of a pair with μ_l + μ_v = ``mu_sum`` (> 0;
    ∞ at 0: no bound for two directions on the horizon)."""
    mu_sum = np.asarray(mu_sum, dtype=float)
    with np.errstate(divide="ignore"):
        return REL_ERROR_K / (min(alpha_x, alpha_y) * mu_sum)


log = logging.getLogger(__name__)
_kernels: dict[Components, "Kernel32"] = {}
_lock = threading.Lock()


def components(brdf) -> Components:
    """The float32 loop's components of a single-lobe model, or Float32Unsupported."""
    from . import ENABLED, components as components64
    if not ENABLED:
        raise Float32Unsupported("float32 needs the compiled kernels (numba), which are off "
                                 "here (numba absent or BRDF_FAST=0)")
    if isinstance(brdf, CompensatedBRDF):
        raise Float32Unsupported("a compensated model's multiple-scattering term is a float64 "
                                 "table: no float32 loop")
    if getattr(brdf, "numpy_only", False):
        raise Float32Unsupported("this model family is evaluated by numpy only: no float32 loop")
    c = components64(brdf)
    if c is None:
        raise Float32Unsupported("this model has no compiled loop (a component without a "
                                 "scalar formula)")
    compose.float32_hooks(c)     # raises naming the component without a float32 form
    if c.ndf.name not in FLOAT32_NDFS:
        why = NOT_FLOAT32.get(c.ndf.name, "its float32 error has not been measured")
        raise Float32Unsupported(f"float32 is offered for ndf={' or ndf='.join(FLOAT32_NDFS)} "
                                 f"only, not ndf={c.ndf.name}: {why}")
    return c


def unsupported(brdf) -> str | None:
    """Why ``brdf`` has no float32 loop, or None when it has one (nothing compiled)."""
    try:
        components(brdf)
        if brdf.lobe2 is not None:
            components(replace(brdf, ndf=brdf.lobe2, lobe2=None, lobe_mix=0.0))
    except Float32Unsupported as exc:
        return str(exc)
    return None


def kernel(brdf) -> "Kernel32":
    """The float32 loop of ``brdf``'s model (Float32Unsupported if none). On first use of
    a model class the compiler process puts it into numba's disk cache (1.5-4 s, under
    its own GIL, as for the float64 loops: compiled here it would hold this server's GIL
    and stall every other request), and this process loads it from there."""
    c = components(brdf)
    with _lock:
        k = _kernels.get(c)
        if k is None:
            module = compose.load32(c)
            if not compose.cached(module, ("f_loop",)):
                reason = CLIENT.compile(Path(module.__file__), "f")
                if reason is not None:       # no compiler process: compile here instead
                    log.warning("compiler process: %s (compiling the float32 loop here)", reason)
            with compose.compiling(module):
                k = Kernel32(c, module)
                k.warm()
            _kernels[c] = k
    return k


def f(brdf, l, v) -> np.ndarray:
    """f(l, v) in float32 (a float32 array) for l, v broadcastable (..., 3): the float32
    loop of each lobe, a second lobe blended in float32."""
    single = replace(brdf, lobe2=None, lobe_mix=0.0)
    out = kernel(single).f(single, l, v)
    if brdf.lobe2 is not None and brdf.lobe_mix > 0:
        second = replace(single, ndf=brdf.lobe2)
        out = blend_lobes(np.float32(brdf.lobe_mix), out, kernel(second).f(second, l, v))
    return out.astype(np.float32, copy=False)


def sample_pairs(alpha_x: float, alpha_y: float, n: int, seed: int = 0) -> tuple[np.ndarray, np.ndarray]:
    """(l, v), (n, 3) float64, for measuring the float32 loop's error: half uniform on the
    upper hemisphere with half of those cosines log-uniform down to 1e-7 (grazing), half
    around the specular peak (l = v mirrored about a normal whose slopes are α times a
    normal deviate times 10^U(−1, 1): where D reads the cancelling half vector divided by
    α; uniform pairs almost never land there at small α)."""
    rng = np.random.default_rng(seed)

    def hemisphere(k):
        u = rng.random(k)
        mu = np.where(u < 0.5, rng.random(k), 10.0 ** rng.uniform(-7.0, 0.0, k))
        mu[u > 0.98] = 0.0                      # on the horizon exactly (θ = 90°)
        phi = rng.random(k) * 2.0 * np.pi
        s = np.sqrt(1.0 - mu * mu)
        return np.stack([s * np.cos(phi), s * np.sin(phi), mu], axis=-1)

    l, v = hemisphere(n), hemisphere(n)
    peak = np.arange(n) % 2 == 1
    k = int(peak.sum())
    scale = 10.0 ** rng.uniform(-1.0, 1.0, (k, 1))
    slopes = rng.normal(size=(k, 2)) * np.array([alpha_x, alpha_y]) * scale
    h = np.concatenate([-slopes, np.ones((k, 1))], axis=-1)
    h /= np.linalg.norm(h, axis=-1, keepdims=True)
    vp = v[peak]
    lp = 2.0 * np.sum(vp * h, axis=-1, keepdims=True) * h - vp
    above = lp[:, 2] > 0.0
    rows = np.flatnonzero(peak)[above]
    l[rows] = lp[above] / np.linalg.norm(lp[above], axis=-1, keepdims=True)
    return l, v


def measure(brdf, n: int = 100_000, seed: int = 0) -> dict:
    """The float32 loop against the float64 numpy path (BRDF.evaluate, the reference) on
    :func:`sample_pairs`: the largest relative error ("rel"), the largest of
    rel · α_min · (μ_l + μ_v) ("k", what REL_ERROR_K bounds) over pairs with a finite,
    nonzero f64 and μ_l + μ_v > 0, and whether the two agree on which values are ∞
    and which are 0."""
    ndf = brdf.ndf
    l, v = sample_pairs(ndf.alpha_x, ndf.alpha_y, n, seed)
    ref = brdf.evaluate(l, v, ("f",))["f"]
    got = f(brdf, l, v).astype(np.float64)
    mu_sum = np.maximum(l[:, 2], 0.0) + np.maximum(v[:, 2], 0.0)
    ok = np.isfinite(ref) & (ref != 0.0) & (mu_sum > 0.0)
    rel = np.abs(got[ok] - ref[ok]) / np.abs(ref[ok])
    return {"rel": float(np.max(rel, initial=0.0)),
            "k": float(np.max(rel * min(ndf.alpha_x, ndf.alpha_y) * mu_sum[ok], initial=0.0)),
            "inf_agree": bool(np.array_equal(np.isinf(got), np.isinf(ref))),
            "zero_agree": bool(np.array_equal(got == 0.0, ref == 0.0)),
            "pairs": int(ref.size)}


__all__ = ["Float32Unsupported", "PARALLEL_MIN", "f", "kernel", "rel_error_bound", "unsupported"]
