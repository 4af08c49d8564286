"""A sphere lit by an environment, rendered by multiple importance sampling.

Orthographic camera along −z (v = +z for every pixel), sphere of radius 1; per pixel the
local frame (t, b, n) of quantities.lit_sphere. L_o = ∫ f(l, v) L(l) (n·l) dω_l is
estimated with the multi-sample balance heuristic (Veach 1997, ch. 9) over three
strategies: the environment's radiance (a piecewise-constant pdf on equal-solid-angle
cells; N/2 samples unless the environment is uniform), cosine-weighted directions (diffuse
lobes) and the NDF's visible normals (Heitz 2018; specular lobe), the last two splitting
the rest of N as the lobes' energies (:func:`_shares`). Each strategy's samples are one
stratified set rotated per pixel (Cranley & Patterson 1976), so pixels' errors are
independent; f is evaluated once per sample for the three channels (evaluate.py), only
where l is upper. ``noise`` states the per-pixel
standard error of the one-sample estimator (mean, max, relative to the mean radiance) and
that of the image mean. (derivation: docs/principled.md §3.1)
"""
from __future__ import annotations

import time

import numpy as np

from ..physics.vectors import direction_deg
from .evaluate import f_samples
from .maps import ENVIRONMENTS

#: Equal-solid-angle cells of the environment's pdf: rows uniform in z, columns in φ.
PDF_ROWS, PDF_COLS = 96, 192
#: The share of the environment's pdf spread uniformly over the sphere, so no direction
#: where L > 0 has p = 0 even if its cell's centre sees L = 0 (a soft edge).
PDF_UNIFORM_SHARE = 0.05


def _stratified(n: int, rng) -> np.ndarray:
    """n points in [0, 1)², one per cell of a near-square jittered grid."""
    cols = int(np.ceil(np.sqrt(n)))
    rows = int(np.ceil(n / cols))
    i = np.arange(n)
    return np.stack([(i % cols + rng.random(n)) / cols, (i // cols + rng.random(n)) / rows], axis=-1)


def _rotated(n: int, pixels: int, rng) -> np.ndarray:
    """(pixels, n, 2): one stratified set shifted by a random offset per pixel, mod 1."""
    return (_stratified(n, rng)[None, :, :] + rng.random((pixels, 1, 2))) % 1.0


def _shares(brdf) -> tuple[float, float]:
    """(specular, diffuse) energies that split the BRDF-sampling budget: the principled
    material's C_spec0 (+ clearcoat) against (1 − metallic)·base colour; else F̄ against
    the diffuse term's E_avg (Kulla-Conty's broad lobe counts as diffuse)."""
    lum = np.array([0.2126, 0.7152, 0.0722])
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
        lum = env.radiance(w, key, colour) @ np.array([0.2126, 0.7152, 0.0722])
        p = lum.ravel() / max(lum.sum(), 1e-300)
        self.p = (1.0 - PDF_UNIFORM_SHARE) * p + PDF_UNIFORM_SHARE / p.size
        self.cdf = np.cumsum(self.p)
        self.cell_sr = 4.0 * np.pi / p.size

    def sample(self, u, rng) -> np.ndarray:
        """Directions for u (..., 2): the cell by u₀ on the CDF, uniform within it."""
        cell = np.minimum(np.searchsorted(self.cdf, u[..., 0] * self.cdf[-1], side="right"), self.p.size - 1)
        row, col = np.divmod(cell, PDF_COLS)
        z = 1.0 - 2.0 * (row + u[..., 1]) / PDF_ROWS
        phi = -np.pi + 2.0 * np.pi * (col + rng.random(u.shape[:-1])) / PDF_COLS
        s = np.sqrt(np.maximum(0.0, 1.0 - z * z))
        return np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=-1)

    def pdf(self, w) -> np.ndarray:
        row = np.clip(((1.0 - w[..., 2]) * 0.5 * PDF_ROWS).astype(int), 0, PDF_ROWS - 1)
        col = np.clip(((np.arctan2(w[..., 1], w[..., 0]) + np.pi) / (2 * np.pi) * PDF_COLS).astype(int),
                      0, PDF_COLS - 1)
        return self.p[row * PDF_COLS + col] / self.cell_sr


def sphere_frames(n: int):
    """Pixel centres on the sphere: (mask (n, n), frames (P, 3, 3) rows t, b, n)."""
    centres = -1.0 + (2.0 * np.arange(n) + 1.0) / n
    y, x = np.meshgrid(centres[::-1], centres, indexing="ij")
    on = x * x + y * y < 1.0
    normal = np.stack([x[on], y[on], np.sqrt(1.0 - x[on] ** 2 - y[on] ** 2)], axis=-1)
    t = np.array([1.0, 0.0, 0.0]) - normal[:, :1] * normal
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    return on, np.stack([t, np.cross(normal, t), normal], axis=-2), centres


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


def render(brdf, environment: str, theta_deg: float, phi_deg: float, n: int, samples: int,
           colour=(1.0, 1.0, 1.0), seed: int = 0) -> dict:
    """Linear RGB radiance (n, n, 3) of the sphere (NaN off it), the background radiance
    (the environment behind the sphere, direction −z), and the sampling report."""
    t0 = time.perf_counter()
    env = ENVIRONMENTS[environment]
    key = direction_deg(theta_deg, phi_deg)
    colour = np.asarray(colour, dtype=float)
    rng = np.random.default_rng(seed)
    on, frame, centres = sphere_frames(n)
    P = len(frame)
    v = frame[:, :, 2]                                  # v = +z in each local frame
    n_env, n_cos, n_vndf = _split(brdf, env, samples)
    local, world = [], []                               # (P, k, 3) per strategy
    if n_env:
        env_pdf = EnvironmentPdf(env, key, colour)
        w = env_pdf.sample(_rotated(n_env, P, rng), rng)
        world.append(w)
        local.append(w @ frame.transpose(0, 2, 1))     # rows t, b, n: l = frame · w
    if n_cos:
        u = _rotated(n_cos, P, rng)
        r, a = np.sqrt(u[..., 0]), 2.0 * np.pi * u[..., 1]
        local.append(np.stack([r * np.cos(a), r * np.sin(a), np.sqrt(np.maximum(0.0, 1.0 - u[..., 0]))], -1))
    if n_vndf:
        # u (P, n, 2): a set per pixel (the sampler broadcasts its (P, 1) frame of v against it)
        m = brdf.ndf.sample_visible(v, _rotated(n_vndf, P, rng))
        local.append(2.0 * np.einsum("pi,psi->ps", v, m)[..., None] * m - v[:, None, :])
    world += [lk @ frame for lk in local[len(world):]]  # w = frameᵀ · l
    l = np.concatenate(local, axis=1)                                   # (P, N, 3) local
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
    L_o = np.stack([np.bincount(pixel, weight[:, c], P) for c in range(3)], axis=-1)
    # one-sample estimates (N × weight; 0 where l is lower): their variance per pixel
    lum = weight @ np.array([0.2126, 0.7152, 0.0722]) * samples
    s1, s2 = np.bincount(pixel, lum, P), np.bincount(pixel, lum * lum, P)
    std_error = np.sqrt(np.maximum(s2 - s1 * s1 / samples, 0.0) / (samples - 1) / samples)
    image = np.full((n, n, 3), np.nan)
    image[on] = L_o
    mean = float(np.mean(L_o @ np.array([0.2126, 0.7152, 0.0722])))
    return {"y": centres[::-1], "x": centres, "radiance": image,   # rows (y), then columns (x)
            "background": env.radiance(np.array([0.0, 0.0, -1.0]), key, colour),
            "samples": {"per_pixel": samples, "environment": n_env, "cosine": n_cos,
                        "visible_normals": n_vndf, "pixels": P, "evaluations": len(pixel)},
            "noise": {"std_error_mean": float(std_error.mean()), "std_error_max": float(std_error.max()),
                      "relative": float(std_error.mean() / mean) if mean > 0 else 0.0,
                      "mean_radiance": mean,
                      # every pixel's samples independent of the others': √Σσ²/P
                      "mean_radiance_error": float(np.sqrt(np.sum(std_error ** 2)) / P)},
            "seconds": time.perf_counter() - t0}


def _vndf_pdf(ndf, l, v, pixel) -> np.ndarray:
    """Density of l (m, 3) reflected about visible normals of v[pixel], both upper:
    G1(v) D(h) / (4 μ_v) = D(h) / (4 (μ_v + μΛ(v))) (Heitz 2018), the denominator once
    per pixel; h = (l + v)/‖l + v‖ exists and v·h > 0 there."""
    s = l + v[pixel]
    h = s / np.sqrt(np.einsum("mi,mi->m", s, s))[:, None]
    return ndf.D(h) / (4.0 * (v[:, 2] + ndf.mu_Lambda(v)))[pixel]


#: The point light's irradiance at normal incidence: π, so a white Lambertian facing it
#: has radiance 1 (the environments' scale).
POINT_IRRADIANCE = np.pi


def render_point(brdf, theta_deg: float, phi_deg: float, n: int, colour=(1.0, 1.0, 1.0)) -> dict:
    """The sphere under one directional light (quantities.lit_sphere, in colour):
    L_o = f(l, v) μ_l E per channel, E = π·colour; black background."""
    t0 = time.perf_counter()
    on, frame, centres = sphere_frames(n)
    l = frame @ direction_deg(theta_deg, phi_deg)
    v = frame[:, :, 2]
    lit = l[:, 2] > 0
    L_o = np.zeros((len(v), 3))
    if lit.any():
        f = f_samples(brdf, l[lit], v[lit], np.arange(int(lit.sum())))
        L_o[lit] = (f if f.ndim == 2 else f[:, None]) * (l[lit, 2] * POINT_IRRADIANCE)[:, None] * colour
    image = np.full((n, n, 3), np.nan)
    image[on] = L_o
    return {"y": centres[::-1], "x": centres, "radiance": image,   # rows (y), then columns (x)
            "background": np.zeros(3),
            "samples": None, "noise": None, "seconds": time.perf_counter() - t0}
