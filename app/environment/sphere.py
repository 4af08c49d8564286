"""The lit sphere: any model on a sphere of radius 1 under a lighting, the one renderer
behind the ``sphere`` and ``sphere_env`` views and ``/materials/sphere``.

A lighting is an environment L(ω) (None: black) plus delta lights; a point light is the
lighting that is one delta. The sphere's outgoing radiance per pixel is
L_o = Σ_k f(l_k, v) ⟨n·l_k⟩ E_k  (each delta: direction l_k, irradiance E_k at normal
incidence; no sampling) + ∫ f(l, v) L(l) ⟨n·l⟩ dω_l  (the environment: multiple-importance
sampling, render.py; its noise stated).

Camera: orthographic along −z, the viewer v = +z for every pixel; n×n pixel centres
(rows y from the top, columns x, in sphere radii). At each pixel the normal is
n = (x, y, √(1−x²−y²)) and the tangent t is +x projected onto the tangent plane (the
direction of α_x), b = n × t; local directions are (·t, ·b, ·n) (:func:`frames_at`, the
one pixel frame). Where a delta's highlight is narrower than a pixel it falls between
pixel centres: the 3×3 pixels around it hold their mean over a sub-grid of spacing
≤ α/2 (at most SUB_MAX² points each), what a camera pixel records.
"""
from __future__ import annotations

from dataclasses import dataclass, field

import numpy as np
from scipy import optimize

from .. import kernels
from ..adaptive import peak
from ..physics.vectors import direction_deg
from .evaluate import f_samples
from .maps import ENVIRONMENTS, Environment
from .render import LUMINANCE, estimate

#: Sub-pixels per side, at most, of a pixel around a delta's highlight (its mean is taken).
SUB_MAX = 256
#: The backdrop behind the sphere is the environment as a pinhole camera with this field
#: of view across the image sees it looking along −z (the sphere itself is drawn by the
#: orthographic camera; an orthographic backdrop would be the one colour L(−z)).
BACKDROP_FOV_DEG = 90.0
#: The point light of the environment views: irradiance π at normal incidence, so a white
#: Lambertian facing it has radiance 1 (the environments' scale).
POINT_IRRADIANCE = np.pi


@dataclass(frozen=True)
class Lighting:
    """An environment (placed by ``key``, scaled by ``colour``) plus delta lights, each
    (world direction, irradiance at normal incidence: a number or r, g, b)."""
    environment: Environment | None = None
    key: np.ndarray = field(default_factory=lambda: np.array([0.0, 0.0, 1.0]))
    colour: np.ndarray = field(default_factory=lambda: np.ones(3))
    deltas: tuple = ()


def point_light(theta_deg: float, phi_deg: float, irradiance=1.0) -> Lighting:
    """One delta at (θ, φ) from the viewer (φ in the image plane from +x)."""
    return Lighting(deltas=((direction_deg(theta_deg, phi_deg), np.asarray(irradiance, dtype=float)),))


def environment_lighting(name: str, theta_deg: float, phi_deg: float, colour=(1.0, 1.0, 1.0)) -> Lighting:
    """The procedural environment ``name`` (maps.py) with its light (key box, zenith,
    sun) at (θ, φ)."""
    return Lighting(ENVIRONMENTS[name], direction_deg(theta_deg, phi_deg), np.asarray(colour, dtype=float))


def frames_at(x, y) -> np.ndarray:
    """The pixel frames (M, 3, 3), rows t, b, n, at image points (x, y) inside the disk."""
    x, y = np.asarray(x, dtype=float), np.asarray(y, dtype=float)
    normal = np.stack([x, y, np.sqrt(np.maximum(1.0 - x * x - y * y, 0.0))], axis=-1)
    t = np.array([1.0, 0.0, 0.0]) - normal[:, :1] * normal
    t /= np.linalg.norm(t, axis=-1, keepdims=True)      # |t| = √(1 − n_x²) > 0 inside the disk
    return np.stack([t, np.cross(normal, t), normal], axis=-2)


def sphere_frames(n: int):
    """Pixel centres on the sphere: (mask (n, n), frames (P, 3, 3) rows t, b, n, centres)."""
    centres = -1.0 + (2.0 * np.arange(n) + 1.0) / n
    y, x = np.meshgrid(centres[::-1], centres, indexing="ij")   # row 0 at the top
    on = x * x + y * y < 1.0
    return on, frames_at(x[on], y[on]), centres


def lit_sphere(brdf, lighting: Lighting, n: int, *, rgb: bool = True, samples: int = 16,
               seed: int = 0) -> dict:
    """The sphere's radiance (n, n, 3) — or (n, n) with ``rgb=False``: f of the model's
    own channel, deltas of grey irradiance only — NaN off the sphere. In colour also
    ``background``: the environment behind the sphere at every pixel (n, n, 3; the
    sphere is drawn over it), black (3,) without one. With an environment ``samples``,
    ``noise`` and ``std_error``, each pixel's standard error of its luminance (n, n; NaN
    off the sphere: what independent renders are averaged with, render.averaged), else
    None. Per delta ``supersampled``; with one delta, no
    environment and ``rgb=False``, ``peak`` (the brightest pixel against the located
    maximum of L_o: a point value, which at small α no pixel mean reaches)."""
    on, frame, centres = sphere_frames(n)
    shape = (n, n, 3) if rgb else (n, n)
    radiance = np.full(shape, np.nan)
    radiance[on] = 0.0
    out = {"y": centres[::-1], "x": centres, "radiance": radiance, "samples": None, "noise": None,
           "std_error": None}
    if rgb:
        out["background"] = np.zeros(3)
    y, x = np.meshgrid(centres[::-1], centres, indexing="ij")
    for direction, irradiance in lighting.deltas:
        radiance[on] += _delta(brdf, frame, direction, irradiance, rgb)
        out["supersampled"] = _supersample(brdf, radiance, x, y, on, direction, irradiance, rgb)
    if lighting.environment is not None:
        if not rgb:
            raise ValueError("an environment lights the sphere in colour (rgb=True)")
        L_o, out["samples"], out["noise"], std_error = estimate(
            brdf, lighting.environment, lighting.key, lighting.colour, frame, samples, seed)
        radiance[on] += L_o
        out["std_error"] = np.full((n, n), np.nan)
        out["std_error"][on] = std_error
        out["background"] = _backdrop(lighting, x, y)
    elif len(lighting.deltas) == 1 and not rgb:
        out["peak"] = _peak(brdf, radiance, *lighting.deltas[0])
    return out


def _f(brdf, l, v, rgb: bool) -> np.ndarray:
    """f at pairs (l, v), both upper: (M, 3) per channel (a grey model: (M,)) with
    ``rgb``, else the model's own channel (M,)."""
    return f_samples(brdf, l, v, np.arange(len(v))) if rgb else kernels.f(brdf, l, v)


def _delta(brdf, frame, direction, irradiance, rgb: bool) -> np.ndarray:
    """f(l, v) ⟨n·l⟩ E at pixels of ``frame`` (M, 3, 3) for one delta."""
    l, v = frame @ direction, frame[:, :, 2]             # v = +z in each local frame
    mu_l = l[:, 2]
    lit = mu_l > 0.0
    value = np.zeros((len(frame), 3) if rgb else len(frame))
    if lit.any():
        f = _f(brdf, l[lit], v[lit], rgb)
        if rgb and f.ndim == 1:
            f = f[:, None]
        value[lit] = f * (mu_l[lit][:, None] if rgb else mu_l[lit]) * irradiance
    return value


def _narrowest_deg(brdf) -> float:
    """The narrowest feature of the specular lobe, in degrees of the view direction:
    the half vector moves half as fast as v, and D falls off over θ_m ≈ α."""
    alphas = [brdf.ndf.alpha_x, brdf.ndf.alpha_y]
    lobe2 = getattr(brdf, "lobe2", None)
    if lobe2 is not None and getattr(brdf, "lobe_mix", 0.0) > 0:
        alphas += [lobe2.alpha_x, lobe2.alpha_y]
    return float(np.rad2deg(2.0 * min(alphas)))


def _supersample(brdf, radiance, x, y, on, direction, irradiance, rgb) -> dict:
    """The 3×3 pixels around the delta's mirror point n = h hold the delta's mean over a
    k×k sub-grid (spacing ≤ α/2, points off the disk count 0) in place of its value at
    the pixel centre."""
    h = direction + np.array([0.0, 0.0, 1.0])
    h /= np.linalg.norm(h)
    n = x.shape[0]
    pixel = 2.0 / n
    k = int(min(SUB_MAX, max(1, np.ceil(2.0 * pixel / np.deg2rad(_narrowest_deg(brdf) / 2)))))
    near = on & (np.abs(x - h[0]) < 1.5 * pixel) & (np.abs(y - h[1]) < 1.5 * pixel)
    if k > 1:
        offsets = (np.arange(k) + 0.5) / k * pixel - pixel / 2
        centre = frames_at(x[near], y[near])
        for (i, j), f0 in zip(zip(*np.nonzero(near)), _delta(brdf, centre, direction, irradiance, rgb)):
            sx, sy = np.meshgrid(x[i, j] + offsets, y[i, j] + offsets)
            inside = sx * sx + sy * sy < 1.0
            values = np.zeros((k * k, 3) if rgb else k * k)
            values[inside.ravel()] = _delta(brdf, frames_at(sx[inside], sy[inside]), direction, irradiance, rgb)
            radiance[i, j] += values.mean(axis=0) - f0
    return {"pixels": int(near.sum()), "per_side": k}


def _peak(brdf, radiance, direction, irradiance) -> dict:
    """The brightest pixel against the maximum of L_o located from the mirror point."""
    h = direction + np.array([0.0, 0.0, 1.0])
    h /= np.linalg.norm(h)

    def value(p):
        return float(_delta(brdf, frames_at(p[:1], p[1:]), direction, irradiance, False)[0])
    res = optimize.minimize(lambda p: -value(p), h[:2], method="Nelder-Mead",
                            options={"xatol": 1e-9, "fatol": 0.0})
    located = (float(res.x[0]), float(res.x[1]), float(-res.fun)) if -res.fun > 0 else None
    return peak(radiance, located, "radiance", "x", "y")


def _backdrop(lighting: Lighting, x, y) -> np.ndarray:
    """The environment behind the sphere (BACKDROP_FOV_DEG) at every pixel."""
    s = np.tan(np.deg2rad(BACKDROP_FOV_DEG) / 2)
    w = np.stack([x * s, y * s, -np.ones_like(x)], axis=-1)
    w /= np.linalg.norm(w, axis=-1, keepdims=True)
    return lighting.environment.radiance(w, lighting.key, lighting.colour)

