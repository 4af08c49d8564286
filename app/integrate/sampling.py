"""Direction samplers for Monte Carlo integrals over l, each with its pdf.

Every sampler draws light directions l for a view direction v and gives the density
of l in the solid-angle measure, over the FULL sphere of l (a sampler may put
directions below the horizon; an estimator counts them as 0). Samplers:

* ``uniform``: the upper hemisphere, pdf = 1/(2π) (Pharr, Jakob, Humphreys,
  "Physically Based Rendering" 4th ed., sec. A.5.2).
* ``cosine``: Malley's method, a uniform point on the unit disk lifted to the
  hemisphere, pdf = μ_l/π (PBR 4th ed., sec. A.5.3).
* ``ndf``: a microfacet normal m with density D(m)(n·m) by inverting the NDF's radial
  CDF in α-stretched slope space (seed 001; Walter et al. 2007, eq. 35-36), then
  l = 2(v·m)m − v; the Jacobian dl = 4|v·m| dm (Walter et al. 2007, eq. 14) gives
  pdf(l) = D(m)(n·m) / (4|v·m|), m = ±h the upper one of the two normals mirroring v to l.
* ``vndf``: visible normals D_v(m) = G1(v) (v·m)⁺ D(m) / (n·v) (Heitz 2014, eq. 38),
  then the same reflection: pdf(l) = G1(v) D(h) / (4 n·v) = D(h) / (4 (μ_v + μΛ(v)))
  (finite at μ_v = 0). GGX by Heitz 2018, "Sampling the GGX Distribution of Visible
  Normals", JCGT 7(4); Beckmann by the slope-space method of Heitz & d'Eon 2014,
  "Importance Sampling Microfacet-Based BSDFs using the Distribution of Visible Normals",
  EGSR (sec. 4, with the 1-D slope marginal inverted by bisection).

Two-lobe models are sampled as the mixture: the lobe is chosen with its weight, and the
pdf is Σ w_k pdf_k. A sampler whose ``supports(brdf)`` is False raises ValueError.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np
from scipy.special import erfc, ndtri

from ..physics.brdf import BRDF
from ..physics.ndf import NDF, SlopeSpaceNDF
from ..physics.numeric import where_valid
from ..physics.vectors import dot, half_vector, reflect

# Primary samples in the OPEN interval (0, 1): u = (k + ½)/2^52 for an integer k drawn
# uniformly from [0, 2^52). Every value is exact in float64 and the largest is
# 1 − 2^-53 < 1, so inverse CDFs never see 0 or 1 (where they return ±inf).
OPEN_UNIFORM_BITS = 52

# Beckmann visible slopes: the 1-D marginal is bracketed in [−SLOPE_BRACKET, min(cot θ,
# SLOPE_BRACKET)]; its mass outside is erfc(8)/2 ≈ 6e-30, far below any test's reach.
SLOPE_BRACKET = 8.0
# Bisection halves the bracket (width ≤ 16) BISECTION_STEPS times: 16/2^60 ≈ 1.4e-17,
# below the spacing of doubles near the slopes that matter.
BISECTION_STEPS = 60


def open_uniform(rng: np.random.Generator, shape) -> np.ndarray:
    """Uniform numbers in the open interval (0, 1) (see OPEN_UNIFORM_BITS)."""
    k = rng.integers(0, 2 ** OPEN_UNIFORM_BITS, size=shape, dtype=np.int64)
    return (k + 0.5) / 2.0 ** OPEN_UNIFORM_BITS


def _unit(x: np.ndarray) -> np.ndarray:
    return x / np.sqrt(dot(x, x))[..., None]


# ---- hemisphere samplers (independent of v) -------------------------------------------

def _uniform_sample(brdf, v, u):
    z = u[..., 0]
    r = np.sqrt(np.maximum(0.0, 1.0 - z * z))
    phi = 2.0 * np.pi * u[..., 1]
    l = np.stack([r * np.cos(phi), r * np.sin(phi), z], axis=-1)
    return np.broadcast_to(l, v.shape[:-1] + l.shape)


def _over(l, v, values):
    """``values`` (a function of l only) broadcast to the shape of the (l, v) pairs."""
    return np.broadcast_to(values, np.broadcast_shapes(l.shape, v.shape)[:-1]).copy()


def _uniform_pdf(brdf, l, v):
    return _over(l, v, np.where(l[..., 2] >= 0, 1.0 / (2.0 * np.pi), 0.0))


def _cosine_sample(brdf, v, u):
    # Malley: (r, φ) uniform on the unit disk, z = √(1 − r²).
    r = np.sqrt(u[..., 0])
    phi = 2.0 * np.pi * u[..., 1]
    l = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(0.0, 1.0 - u[..., 0]))], axis=-1)
    return np.broadcast_to(l, v.shape[:-1] + l.shape)


def _cosine_pdf(brdf, l, v):
    return _over(l, v, np.maximum(l[..., 2], 0.0) / np.pi)


# ---- D(m)(n·m) ------------------------------------------------------------------------

def _slopes_to_normal(X, Y):
    """m ∝ (−X, −Y, 1) for unstretched slopes (X, Y) (Heitz 2014, eq. 2)."""
    return _unit(np.stack([-X, -Y, np.ones_like(X)], axis=-1))


def sample_ndf_normals(ndf: SlopeSpaceNDF, u1, u2) -> np.ndarray:
    """m with density D(m)(n·m): stretched radius from the tail mass 1 − u1 (the
    ccdf form keeps precision in the tail), ψ = 2π u2, then unstretch."""
    r = np.sqrt(ndf.radial_ccdf_inv(1.0 - u1))
    psi = 2.0 * np.pi * u2
    return _slopes_to_normal(ndf.alpha_x * r * np.cos(psi), ndf.alpha_y * r * np.sin(psi))


def _ndf_pdf_one(ndf: NDF, l, v):
    """pdf(l) = D(m)(n·m)/(4|v·m|) with m = ±h, the one in the upper hemisphere
    (l = 2(v·m)m − v for both m and −m; only the upper one has D > 0)."""
    h, exists = half_vector(l, v)
    m = h * np.where(h[..., 2] < 0, -1.0, 1.0)[..., None]
    vm = np.abs(dot(v, m))
    Dm = np.where(exists, ndf.D(m), 0.0)
    return where_valid(exists & (vm > 0) & (Dm > 0), [Dm, m[..., 2], vm],
                       lambda d, mz, c: d * mz / (4.0 * c), 0.0)


def _ndf_sample_one(ndf, v, u):
    m = sample_ndf_normals(ndf, u[..., 0], u[..., 1])
    return reflect(v[..., None, :], m)


# ---- visible normals --------------------------------------------------------------------

def _stretched_view(ndf, v):
    """v in the α-stretched configuration, where the NDF is the α = 1 one."""
    return _unit(np.stack([ndf.alpha_x * v[..., 0], ndf.alpha_y * v[..., 1], v[..., 2]], axis=-1))


def _ggx_visible_normals(ndf, v, u):
    """Heitz 2018, JCGT 7(4), listing 1: stretch v; a uniform point on the disk,
    warped onto the projection of the visible hemisphere (half disk squeezed by
    s = (1 + V_z)/2); lift to the hemisphere about V; unstretch."""
    V = _stretched_view(ndf, v)[..., None, :]                 # (k, 1, 3)
    len2 = V[..., 0] ** 2 + V[..., 1] ** 2
    # Orthonormal basis (T1, T2, V); T1 = (1, 0, 0) at normal incidence.
    inv_len = where_valid(len2 > 0, [len2], lambda x: 1.0 / np.sqrt(x), 0.0)
    T1 = np.where((len2 > 0)[..., None],
                  np.stack([-V[..., 1] * inv_len, V[..., 0] * inv_len, np.zeros_like(len2)], axis=-1),
                  np.array([1.0, 0.0, 0.0]))
    T2 = np.cross(V, T1)
    r = np.sqrt(u[..., 0])
    phi = 2.0 * np.pi * u[..., 1]
    t1 = r * np.cos(phi)
    t2 = r * np.sin(phi)
    s = 0.5 * (1.0 + V[..., 2])
    t2 = (1.0 - s) * np.sqrt(np.maximum(0.0, 1.0 - t1 * t1)) + s * t2
    tz = np.sqrt(np.maximum(0.0, 1.0 - t1 * t1 - t2 * t2))
    Nh = t1[..., None] * T1 + t2[..., None] * T2 + tz[..., None] * V
    return _unit(np.stack([ndf.alpha_x * Nh[..., 0], ndf.alpha_y * Nh[..., 1],
                           np.maximum(0.0, Nh[..., 2])], axis=-1))


def _beckmann_slope_marginal_inv(cos_t, sin_t, u):
    """x̃ with density ∝ (cosθ − x̃ sinθ)⁺ e^{−x̃²}/√π (the visible slope along v's
    azimuth, α = 1; Heitz & d'Eon 2014, sec. 4). Its unnormalised CDF is
    A(x) = cosθ erfc(−x)/2 + sinθ e^{−x²}/(2√π) for x ≤ cot θ; A(x) = u·A(cot θ) is
    solved by bisection (A is increasing there)."""
    def A(x):
        return 0.5 * cos_t * erfc(-x) + sin_t * np.exp(-x * x) / (2.0 * np.sqrt(np.pi))

    cot = where_valid(sin_t > 0, [cos_t, sin_t], lambda c, s: c / s, np.inf)
    hi = np.minimum(cot, SLOPE_BRACKET)
    target = u * A(hi)
    lo = np.full_like(target, -SLOPE_BRACKET)
    hi = np.broadcast_to(hi, target.shape).copy()
    for _ in range(BISECTION_STEPS):
        mid = 0.5 * (lo + hi)
        below = A(mid) < target
        lo = np.where(below, mid, lo)
        hi = np.where(below, hi, mid)
    return 0.5 * (lo + hi)


def _beckmann_visible_normals(ndf, v, u):
    """Slope-space visible normals for Beckmann (Heitz & d'Eon 2014): stretch v, sample
    the slope along its azimuth from the visible marginal and the other slope from the
    Gaussian e^{−ỹ²}/√π (the α = 1 slopes are independent), rotate, unstretch."""
    V = _stretched_view(ndf, v)[..., None, :]
    sin_t = np.sqrt(V[..., 0] ** 2 + V[..., 1] ** 2)
    cos_t = V[..., 2]
    inv = where_valid(sin_t > 0, [sin_t], lambda s: 1.0 / s, 0.0)
    cos_p = np.where(sin_t > 0, V[..., 0] * inv, 1.0)
    sin_p = np.where(sin_t > 0, V[..., 1] * inv, 0.0)
    x = _beckmann_slope_marginal_inv(cos_t, sin_t, u[..., 0])
    y = ndtri(u[..., 1]) / np.sqrt(2.0)                       # N(0, ½): e^{−y²}/√π
    xr = cos_p * x - sin_p * y
    yr = sin_p * x + cos_p * y
    return _slopes_to_normal(ndf.alpha_x * xr, ndf.alpha_y * yr)


VISIBLE_NORMALS: dict[str, Callable] = {
    "ggx": _ggx_visible_normals,
    "beckmann": _beckmann_visible_normals,
}


def _vndf_sample_one(ndf, v, u):
    m = VISIBLE_NORMALS[ndf.name](ndf, v, u)
    return reflect(v[..., None, :], m)


def _vndf_pdf_one(ndf: NDF, l, v):
    """pdf(l) = G1(v) D(h) / (4 n·v) = D(h) / (4 (μ_v + μΛ(v))) for v·h > 0 (always,
    where h exists); G1 is the NDF's own Smith G1, which normalises D_v."""
    h, exists = half_vector(l, v)
    denom = 4.0 * (v[..., 2] + ndf.mu_Lambda(v))
    Dh = np.where(exists, ndf.D(np.where(exists[..., None], h, np.array([0.0, 0.0, 1.0]))), 0.0)
    return where_valid(exists & (denom > 0), [Dh, denom], lambda d, c: d / c, 0.0)


# ---- mixtures over lobes ----------------------------------------------------------------

def _lobe_ndfs(brdf: BRDF) -> list[tuple[float, NDF]]:
    return [(w, lobe.ndf) for w, lobe in brdf.lobes() if w > 0]


def _mixture(sample_one, pdf_one):
    def sample(brdf, v, u):
        lobes = _lobe_ndfs(brdf)
        if len(lobes) == 1:
            return sample_one(lobes[0][1], v, u)
        out = np.empty(v.shape[:-1] + u.shape[:-1] + (3,))
        edges = np.cumsum([w for w, _ in lobes])
        choice = np.minimum(np.searchsorted(edges / edges[-1], u[..., 2], side="right"), len(lobes) - 1)
        for k, (_, ndf) in enumerate(lobes):
            pick = choice == k
            if pick.any():
                out[..., pick, :] = sample_one(ndf, v, u[pick])
        return out

    def pdf(brdf, l, v):
        return sum(w * pdf_one(ndf, l, v) for w, ndf in _lobe_ndfs(brdf))
    return sample, pdf


def _has_radial_inverse(brdf: BRDF) -> bool:
    return all(isinstance(ndf, SlopeSpaceNDF) for _, ndf in _lobe_ndfs(brdf))


def _has_vndf(brdf: BRDF) -> bool:
    return all(ndf.name in VISIBLE_NORMALS for _, ndf in _lobe_ndfs(brdf))


@dataclass(frozen=True)
class Sampler:
    """A direction sampler: ``sample`` draws l for each v, ``pdf`` is its density."""
    name: str
    label: str
    description: str
    supports: Callable[[BRDF], bool]
    _sample: Callable
    _pdf: Callable

    def check(self, brdf: BRDF) -> None:
        if not self.supports(brdf):
            names = sorted({ndf.name for _, ndf in _lobe_ndfs(brdf)})
            raise ValueError(f"no {self.name} sampler for ndf={', '.join(names)} "
                             f"(sampler={self.name} supports: {SUPPORTED_NDFS.get(self.name, 'every NDF')})")

    def sample(self, brdf: BRDF, v, n: int, rng: np.random.Generator | int):
        """l of shape v.shape[:-1] + (n, 3) and pdf(l) of shape v.shape[:-1] + (n,).

        The same primary samples serve every v (common random numbers: a curve E(μ) is
        smooth in μ; each point is still an unbiased estimate)."""
        self.check(brdf)
        rng = np.random.default_rng(rng) if not isinstance(rng, np.random.Generator) else rng
        v = np.asarray(v, dtype=float)
        u = open_uniform(rng, (int(n), 3))
        l = self._sample(brdf, v, u)
        return l, self._pdf(brdf, l, v[..., None, :])

    def pdf(self, brdf: BRDF, l, v) -> np.ndarray:
        """The density of l given v (solid-angle measure over the whole sphere)."""
        self.check(brdf)
        return self._pdf(brdf, np.asarray(l, dtype=float), np.asarray(v, dtype=float))


SUPPORTED_NDFS = {"vndf": ", ".join(VISIBLE_NORMALS)}

_ndf_sample, _ndf_pdf = _mixture(_ndf_sample_one, _ndf_pdf_one)
_vndf_sample, _vndf_pdf = _mixture(_vndf_sample_one, _vndf_pdf_one)

SAMPLERS: dict[str, Sampler] = {s.name: s for s in [
    Sampler("uniform", "uniform hemisphere", "pdf = 1/(2π) over the upper hemisphere",
            lambda brdf: True, _uniform_sample, _uniform_pdf),
    Sampler("cosine", "cosine-weighted (Malley)", "pdf = cos θ_l / π",
            lambda brdf: True, _cosine_sample, _cosine_pdf),
    Sampler("ndf", "D·cos of m, reflected", "m ~ D(m)(n·m), l = 2(v·m)m − v; "
            "pdf = D(m)(n·m)/(4|v·m|)", _has_radial_inverse, _ndf_sample, _ndf_pdf),
    Sampler("vndf", "visible normals, reflected", "m ~ G1(v)(v·m)⁺D(m)/(n·v) (Heitz 2018 for "
            "GGX, Heitz & d'Eon 2014 for Beckmann); pdf = G1(v)D(h)/(4 n·v)",
            _has_vndf, _vndf_sample, _vndf_pdf),
]}


# ---- goodness of fit --------------------------------------------------------------------

#: Pearson's χ² needs expected counts of at least about 5 per cell (Cochran 1954); cells
#: below are pooled (smallest first) until every cell reaches it.
MIN_EXPECTED = 5.0
#: Gauss-Legendre points per axis inside each bin for the expected counts.
BIN_GAUSS_ORDER = 8


def hemisphere_cells(cos_edges, phi_edges, order: int = BIN_GAUSS_ORDER):
    """Gauss nodes of each (cos θ, φ) bin: directions (nc, nφ, order², 3) and weights
    (same shape without the 3), so that Σ w·g ≈ ∫_bin g dω (dω = d cos θ dφ)."""
    from ..physics.gauss import gauss_legendre_01
    x, w = gauss_legendre_01(order)
    c0, c1 = np.asarray(cos_edges[:-1]), np.asarray(cos_edges[1:])
    p0, p1 = np.asarray(phi_edges[:-1]), np.asarray(phi_edges[1:])
    c = c0[:, None] + (c1 - c0)[:, None] * x                     # (nc, order)
    p = p0[:, None] + (p1 - p0)[:, None] * x                     # (nφ, order)
    cc = c[:, None, :, None]
    pp = p[None, :, None, :]
    s = np.sqrt(np.maximum(0.0, 1.0 - cc * cc))
    dirs = np.stack(np.broadcast_arrays(s * np.cos(pp), s * np.sin(pp), cc), axis=-1)
    wts = ((c1 - c0)[:, None, None, None] * (p1 - p0)[None, :, None, None]
           * w[None, None, :, None] * w[None, None, None, :])
    nc, nphi = len(c0), len(p0)
    return dirs.reshape(nc, nphi, order * order, 3), wts.reshape(nc, nphi, order * order)


def bin_probabilities(pdf_of_l, cos_edges, phi_edges) -> np.ndarray:
    """∫ pdf over each (cos θ, φ) bin of the upper hemisphere, shape (nc, nφ)."""
    dirs, wts = hemisphere_cells(cos_edges, phi_edges)
    return np.einsum("abk,abk->ab", pdf_of_l(dirs), wts)


def histogram(l, cos_edges, phi_edges) -> tuple[np.ndarray, int]:
    """Counts of upper-hemisphere directions per (cos θ, φ) bin, and the count below."""
    l = np.asarray(l).reshape(-1, 3)
    upper = l[:, 2] >= 0
    phi = np.arctan2(l[upper, 1], l[upper, 0])
    counts, _, _ = np.histogram2d(l[upper, 2], phi, bins=[cos_edges, phi_edges])
    return counts, int((~upper).sum())


def chi_square(observed, expected) -> dict:
    """Pearson's χ² of counts against expected counts (same total), with cells of
    expected count below MIN_EXPECTED pooled; p-value from the χ² law with
    (cells − 1) degrees of freedom."""
    from scipy.stats import chi2
    obs = np.asarray(observed, dtype=float).ravel()
    exp = np.maximum(np.asarray(expected, dtype=float).ravel(), 0.0)
    # a count where the density is exactly 0 is a definite misfit, before any pooling
    impossible = bool(np.any(obs[exp == 0] > 0))
    order = np.argsort(exp)
    obs, exp = obs[order], exp[order]
    small = int(np.sum(exp < MIN_EXPECTED))
    if small:
        # pool the smallest cells: all those below MIN_EXPECTED, and more until the pool
        # itself reaches it
        k = max(small, int(np.searchsorted(np.cumsum(exp), MIN_EXPECTED, side="left")) + 1)
        obs = np.concatenate([[obs[:k].sum()], obs[k:]])
        exp = np.concatenate([[exp[:k].sum()], exp[k:]])
    keep = exp > 0
    stat = float(np.sum((obs[keep] - exp[keep]) ** 2 / exp[keep]))
    dof = int(keep.sum()) - 1
    p = 0.0 if impossible or dof < 1 else float(chi2.sf(stat, dof))
    return {"chi2": stat, "dof": dof, "p_value": p, "cells": int(keep.sum())}


def goodness_of_fit(l, pdf_of_l, cos_edges, phi_edges) -> dict:
    """χ² of sampled directions ``l`` against the density ``pdf_of_l`` on (cos θ, φ)
    bins of the upper hemisphere plus one cell for everything below the horizon (its
    expected mass is 1 − the sum over the bins)."""
    n = int(np.asarray(l).reshape(-1, 3).shape[0])
    counts, below = histogram(l, cos_edges, phi_edges)
    prob = bin_probabilities(pdf_of_l, cos_edges, phi_edges)
    expected = np.append(n * prob.ravel(), n * (1.0 - prob.sum()))
    result = chi_square(np.append(counts.ravel(), below), expected)
    result.update(counts=counts, expected=n * prob, below=below, below_expected=n * (1.0 - prob.sum()))
    return result
