"""Samplers of light directions l for a view v, for Monte Carlo integrals over l, with pdfs.

Each pdf is in the solid-angle measure over the FULL sphere of l (a sampler may put l below
the horizon; estimators count it as 0). Two-lobe models are sampled as the mixture, pdf
Σ w_k pdf_k; a sampler whose ``supports(brdf)`` is False raises ValueError.
(derivation: docs/albedo.md §6)

* ``uniform`` (pdf 1/(2π)), ``cosine`` (Malley's method, pdf μ_l/π): the upper hemisphere
  (Pharr, Jakob, Humphreys, "Physically Based Rendering" 4th ed., sec. A.5.2-A.5.3);
* ``ndf``: m with density D(m)(n·m) in α-stretched slopes (Walter et al. 2007), then
  l = 2(v·m)m − v: pdf(l) = D(m)(n·m) / (4|v·m|), m = ±h the upper normal mirroring v to l;
* ``vndf``: visible normals (Heitz 2014, eq. 38): pdf(l) = D(h) / (4 (μ_v + μΛ(v))), finite
  at μ_v = 0. GGX by Heitz 2018, "Sampling the GGX Distribution of Visible Normals"; Beckmann
  by Heitz & d'Eon 2014, "Importance Sampling Microfacet-Based BSDFs using the Distribution
  of Visible Normals" (1-D slope marginal inverted by bisection)."""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from ..physics.brdf import BRDF
from ..physics.ndf import NDF, NDFS, SlopeSpaceNDF
from ..physics.numeric import where_valid
from ..physics.vectors import dot, half_vector, reflect, slopes_to_normal

# Primary samples in the OPEN interval (0, 1): u = (k + ½)/2^52 for an integer k drawn
# uniformly from [0, 2^52). Every value is exact in float64 and the largest is
# 1 − 2^-53 < 1, so inverse CDFs never see 0 or 1 (where they return ±inf).
OPEN_UNIFORM_BITS = 52

def open_uniform(rng: np.random.Generator, shape) -> np.ndarray:
    """Uniform numbers in the open interval (0, 1) (see OPEN_UNIFORM_BITS)."""
    k = rng.integers(0, 2 ** OPEN_UNIFORM_BITS, size=shape, dtype=np.int64)
    return (k + 0.5) / 2.0 ** OPEN_UNIFORM_BITS


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

def sample_ndf_normals(ndf: SlopeSpaceNDF, u1, u2) -> np.ndarray:
    """m with density D(m)(n·m): stretched radius from the tail mass 1 − u1 (the
    ccdf form keeps precision in the tail), ψ = 2π u2, then unstretch."""
    r = np.sqrt(ndf.radial_ccdf_inv(1.0 - u1))
    psi = 2.0 * np.pi * u2
    return slopes_to_normal(ndf.alpha_x * r * np.cos(psi), ndf.alpha_y * r * np.sin(psi))


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


# ---- visible normals (each NDF's own sample_visible) ------------------------------------

def _vndf_sample_one(ndf, v, u):
    m = ndf.sample_visible(v, u)
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
    return all(ndf.sample_visible is not None for _, ndf in _lobe_ndfs(brdf))


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
                             f"(sampler={self.name} supports: {_supported(self.name)})")

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


def _supported(sampler_name: str) -> str:
    """The NDFs a sampler supports, for its error message."""
    if sampler_name != "vndf":
        return "every NDF"
    return ", ".join(n for n, cls in NDFS.items() if cls.sample_visible is not None)

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
