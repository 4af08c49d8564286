"""The environment's share of the lit sphere (sphere.py), by multiple importance sampling.

Per pixel, in its local frame (t, b, n; sphere.frames_at), v = +z: L_o = ∫ f(l, v) L(l) (n·l) dω_l is
estimated with the multi-sample balance heuristic (Veach 1997, ch. 9) over three
strategies: the environment's radiance (a piecewise-constant pdf on equal-solid-angle
cells; N/2 samples unless the environment is uniform), cosine-weighted directions (diffuse
lobes) and the NDF's visible normals (Heitz 2018; specular lobe), the last two splitting
the rest of N as the lobes' energies (:func:`_shares`). Each strategy's samples are a
jittered grid drawn per pixel (:func:`_jittered`), so pixels' errors are independent; f is evaluated once per sample for the three channels (evaluate.py), where
l is upper, in blocks of pixels (CHUNK_PIXELS). ``noise`` states the per-pixel standard
error of the one-sample estimator (mean, max; ``relative``: their RMS over the mean
radiance, the image's relative RMS error) and that of the image mean; ``std_error`` per
pixel, from which independent renders are averaged (:func:`averaged`). (derivation:
docs/principled.md §3.1)
"""
from __future__ import annotations

import math

import numpy as np

from .evaluate import f_samples

#: Equal-solid-angle cells of the environment's pdf: rows uniform in z, columns in φ.
PDF_ROWS, PDF_COLS = 96, 192
#: Guide-table entries per cell of the environment's CDF: inverting it for u₀ starts at
#: most a few cells before the answer (cells narrower than 1/(4·cells) of the total:
#: the dim ones, near the uniform share's floor 0.05/cells, are crossed in ≤ 5 steps).
GUIDE_PER_CELL = 4
#: Pixels estimated together: each of their (pixels × samples) temporaries, ~0.4 MB at
#: 16 samples, stays in a core's cache; the whole 256² sphere's (20 MB) went through
#: memory for every numpy operation. The random numbers are drawn before, for all pixels:
#: the image does not depend on it.
CHUNK_PIXELS = 4096
#: Rec. 709 luminance of linear RGB: the noise is stated on it.
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
#: The share of the environment's pdf spread uniformly over the sphere, so no direction
#: where L > 0 has p = 0 even if its cell's centre sees L = 0 (a soft edge).
PDF_UNIFORM_SHARE = 0.05


def _grid(n: int) -> tuple[int, int]:
    """(cols, rows), cols·rows = n, as near square as n allows (a prime n: n × 1)."""
    rows = max(d for d in range(1, math.isqrt(n) + 1) if n % d == 0)
    return n // rows, rows


def _jittered(n: int, pixels: int, rng) -> np.ndarray:
    """(pixels, n, 2): per pixel, one point uniform in each cell of a cols × rows grid of
    the unit square (cols·rows = n, so the cells tile it: the sum over the set is an
    unbiased, stratified estimate), each pixel its own points. Not a rotated set (Cranley
    & Patterson 1976): the samplers' maps are not periodic, and a set wrapped around the
    square's edge loses its stratification there (twice the error for visible normals)."""
    cols, rows = _grid(n)
    i = np.arange(n)
    x = rng.random((pixels, n, 2))
    x[..., 0] += i % cols
    x[..., 0] /= cols
    x[..., 1] += i // cols
    x[..., 1] /= rows
    return x


def _shares(brdf) -> tuple[float, float]:
    """(specular, diffuse) energies that split the BRDF-sampling budget: the principled
    material's C_spec0 (+ clearcoat) against (1 − metallic)·base colour; else F̄ against
    the diffuse term's E_avg (Kulla-Conty's broad lobe counts as diffuse)."""
    lum = LUMINANCE
    m = getattr(brdf, "material", None)
    if m is not None:
        spec = float(lum @ m.specular_color) + 0.01 * m.clearcoat
        return spec, float((1 - m.metallic) * (lum @ m.base_linear + m.sheen))
    ms = getattr(brdf, "multiscatter", None)
    diffuse = brdf.diffuse_albedo_avg()[0] + (ms.albedo_average() if ms is not None else 0.0)
    return float(brdf.fresnel.F_avg()), float(diffuse)


class EnvironmentPdf:
    """A piecewise-constant density over the sphere ∝ luminance of L, mixed with uniform."""

    def __init__(self, env, key, colour):
        z = 1.0 - 2.0 * (np.arange(PDF_ROWS) + 0.5) / PDF_ROWS
        phi = -np.pi + 2.0 * np.pi * (np.arange(PDF_COLS) + 0.5) / PDF_COLS
        s = np.sqrt(1.0 - z * z)
        w = np.stack(np.broadcast_arrays(s[:, None] * np.cos(phi), s[:, None] * np.sin(phi), z[:, None]), -1)
        lum = env.radiance(w, key, colour) @ LUMINANCE
        p = lum.ravel() / max(lum.sum(), 1e-300)
        self.p = (1.0 - PDF_UNIFORM_SHARE) * p + PDF_UNIFORM_SHARE / p.size
        self.cdf = np.cumsum(self.p)
        self.cell_sr = 4.0 * np.pi / p.size
        self.density = self.p / self.cell_sr
        # the cell of x = u₀·G is the first i with cdf_G[i] > x; the guide table holds it
        # for each integer j = ⌊x⌋ (Chen & Asau 1974), a start a few steps from the answer
        size = GUIDE_PER_CELL * p.size
        self.cdf_guide = self.cdf * (size / self.cdf[-1])
        self.cdf_guide[-1] = np.inf                      # the last cell takes u₀·G's rounding
        self.guide = np.searchsorted(self.cdf_guide, np.arange(size), side="right")

    def cell(self, u0) -> np.ndarray:
        """The cell of u₀ ∈ [0, 1): the first i with CDF[i] > u₀ (inversion of the CDF),
        from the guide table's start, stepping forward while CDF[i] ≤ u₀."""
        x = u0 * len(self.guide)
        cell = self.guide[np.minimum(x.astype(np.intp), len(self.guide) - 1)]
        todo = np.flatnonzero(self.cdf_guide[cell] <= x)
        while todo.size:
            cell[todo] += 1
            todo = todo[self.cdf_guide[cell[todo]] <= x[todo]]
        return cell

    def sample(self, u) -> np.ndarray:
        """Directions for u (..., 3): the cell by u₀ on the CDF, uniform within it (u₁ in
        z, u₂ in φ)."""
        row, col = np.divmod(self.cell(u[..., 0].ravel()).reshape(u.shape[:-1]), PDF_COLS)
        z = 1.0 - 2.0 * (row + u[..., 1]) / PDF_ROWS
        phi = -np.pi + 2.0 * np.pi * (col + u[..., 2]) / PDF_COLS
        s = np.sqrt(np.maximum(0.0, 1.0 - z * z))
        return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=-1)

    def pdf(self, w) -> np.ndarray:
        row = np.clip(((1.0 - w[..., 2]) * 0.5 * PDF_ROWS).astype(int), 0, PDF_ROWS - 1)
        col = np.clip(((np.arctan2(w[..., 1], w[..., 0]) + np.pi) / (2 * np.pi) * PDF_COLS).astype(int),
                      0, PDF_COLS - 1)
        return self.density[row * PDF_COLS + col]


def _split(brdf, env, samples: int) -> tuple[int, int, int]:
    """(environment, cosine, visible-normal) samples per pixel: N/2 from the environment
    unless it is uniform, the rest split as the lobes' energies (:func:`_shares`)."""
    n_env = samples // 2 if env.sampled else 0
    spec, diffuse = _shares(brdf)
    rest = samples - n_env
    n_vndf = 0
    if getattr(brdf.ndf, "sample_visible", None) is not None and spec > 0:
        n_vndf = int(np.clip(round(rest * spec / (spec + diffuse)), 1, rest - (diffuse > 0)))
    return n_env, rest - n_vndf, n_vndf


def estimate(brdf, env, key, colour, frame, samples: int, seed: int):
    """L_o (P, 3) at the pixels of ``frame`` (P, 3, 3) under the environment ``env``
    placed by ``key``, scaled by ``colour``; the sampling report, the noise and each
    pixel's standard error of its luminance (P,)."""
    colour = np.asarray(colour, dtype=float)
    rng = np.random.default_rng(seed)
    P = len(frame)
    split = _split(brdf, env, samples)
    env_pdf = EnvironmentPdf(env, key, colour) if split[0] else None
    # every random number first, so that the pixel blocks below do not change the image
    u = []
    for i, k in enumerate(split):
        u.append(_jittered(k, P, rng) if k else np.empty((P, 0, 2)))
        if i == 0 and k:                                # the environment's φ within a cell
            u[0] = np.concatenate([u[0], rng.random((P, k, 1))], axis=-1)
    sums = np.zeros((P, 5))                            # Σ weight (r, g, b), Σ N·lum, Σ (N·lum)²
    evaluations = 0
    for a in range(0, P, CHUNK_PIXELS):
        block = slice(a, a + CHUNK_PIXELS)
        evaluations += _estimate(brdf, env, key, colour, env_pdf, frame[block], split,
                                 [x[block] for x in u], sums[block])
    L_o, s1, s2 = sums[:, :3], sums[:, 3], sums[:, 4]
    std_error = np.sqrt(np.maximum(s2 - s1 * s1 / samples, 0.0) / (samples - 1) / samples)
    report = {"per_pixel": samples, "environment": split[0], "cosine": split[1],
              "visible_normals": split[2], "pixels": P, "evaluations": evaluations}
    return L_o, report, stated_noise(L_o, std_error), std_error


def averaged(renders) -> tuple[np.ndarray, np.ndarray]:
    """k independent renders (L_o, σ) of one image, each pixel's σ its standard error,
    averaged pixel by pixel: (Σ L_o / k, √(Σ σ²) / k) — the variance of a mean of
    independent estimates is the sum of their variances over k² (Bienaymé). The page's
    refinement at rest (static/js/panels/refine.js) does the same with the data route's
    ``std_error``."""
    radiance = np.mean([r for r, _ in renders], axis=0)
    return radiance, np.sqrt(np.sum([s * s for _, s in renders], axis=0)) / len(renders)


def stated_noise(L_o: np.ndarray, std_error: np.ndarray) -> dict:
    """The noise of an image L_o (P, 3) whose pixels' luminances have standard errors
    ``std_error`` (P,), each pixel estimated independently of the others."""
    mean = float(np.mean(L_o @ LUMINANCE))
    P = len(std_error)
    return {"std_error_mean": float(std_error.mean()), "std_error_max": float(std_error.max()),
            # RMS over the pixels, relative to the mean: the image's relative RMS
            # error (the mean σ understated it 2.5x where a few highlight pixels
            # carry most of the error: a metal, a sun)
            "relative": float(np.sqrt(np.mean(std_error ** 2)) / mean) if mean > 0 else 0.0,
            "mean_radiance": mean,
            # every pixel's samples independent of the others': √Σσ²/P
            "mean_radiance_error": float(np.sqrt(np.sum(std_error ** 2)) / P)}


def _estimate(brdf, env, key, colour, env_pdf, frame, split, u, sums) -> int:
    """One block of pixels (frames (p, 3, 3)): adds each pixel's Σ weight (r, g, b),
    Σ N·lum and Σ (N·lum)² of its one-sample estimates to ``sums`` (p, 5); returns how
    many pairs it evaluated (those with l upper)."""
    n_env, n_cos, n_vndf = split
    p, samples = len(frame), sum(split)
    v = frame[:, :, 2]                                  # v = +z in each local frame
    local, world = [], []                               # (p, k, 3) per strategy
    if n_env:
        w = env_pdf.sample(u[0])
        world.append(w)
        local.append(w @ frame.transpose(0, 2, 1))     # rows t, b, n: l = frame · w
    if n_cos:
        r, a = np.sqrt(u[1][..., 0]), 2.0 * np.pi * u[1][..., 1]
        local.append(np.stack([r * np.cos(a), r * np.sin(a), np.sqrt(np.maximum(0.0, 1.0 - u[1][..., 0]))], -1))
    if n_vndf:
        # u (p, n, 2): a set per pixel (the sampler broadcasts its (p, 1) frame of v against it)
        m = brdf.ndf.sample_visible(v, u[2])
        local.append(2.0 * np.einsum("pi,psi->ps", v, m)[..., None] * m - v[:, None, :])
    world += [lk @ frame for lk in local[len(world):]]  # w = frameᵀ · l
    l = np.concatenate(local, axis=1)                                   # (p, N, 3) local
    up = l[..., 2] > 0                  # every term below is evaluated where l is upper only
    pixel = np.nonzero(up)[0]
    lu, world = l[up], np.concatenate(world, axis=1)[up]
    pdf = (n_cos / np.pi) * lu[:, 2]
    if n_env:
        pdf += n_env * env_pdf.pdf(world)
    if n_vndf:
        pdf += n_vndf * _vndf_pdf(brdf.ndf, lu, v, pixel)
    f = f_samples(brdf, lu, v, pixel)
    f_cos = f * (lu[:, 2] / pdf) if f.ndim == 1 else f * (lu[:, 2] / pdf)[:, None]
    weight = env.radiance(world, key, colour) * (f_cos[:, None] if f.ndim == 1 else f_cos)
    for c in range(3):
        sums[:, c] += np.bincount(pixel, weight[:, c], p)
    lum = weight @ LUMINANCE * samples                  # one-sample estimates (0 where l is lower)
    sums[:, 3] += np.bincount(pixel, lum, p)
    sums[:, 4] += np.bincount(pixel, lum * lum, p)
    return len(pixel)


def _vndf_pdf(ndf, l, v, pixel) -> np.ndarray:
    """Density of l (m, 3) reflected about visible normals of v[pixel], both upper:
    G1(v) D(h) / (4 μ_v) = D(h) / (4 (μ_v + μΛ(v))) (Heitz 2018), the denominator once
    per pixel; h = (l + v)/‖l + v‖ exists and v·h > 0 there."""
    s = l + v[pixel]
    h = s / np.sqrt(np.einsum("mi,mi->m", s, s))[:, None]
    return ndf.D(h) / (4.0 * (v[:, 2] + ndf.mu_Lambda(v)))[pixel]
