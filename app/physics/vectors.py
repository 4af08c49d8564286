"""Directions in the local frame n = +z, t = +x, b = +y; ω = (sinθ cosφ, sinθ sinφ, cosθ).

Directions are float64 arrays of shape (..., 3). Helpers here are the only place where
spherical angles become vectors, so the exact zeros at the poles and the horizon are
produced once, correctly.
"""
from __future__ import annotations

import numpy as np

from .numeric import where_valid


def _sin_cos_deg(angle_deg):
    """sin and cos of an angle in degrees, exact at multiples of 90°.

    ``np.cos(np.pi / 2)`` is 6.1e-17, not 0: a direction at θ = 90° would then sit just
    above the horizon and Λ would be huge instead of infinite. cos x = sin(90° − x) is 0
    exactly at x = 90°.
    """
    a = np.asarray(angle_deg, dtype=float)
    return np.sin(np.deg2rad(a)), np.sin(np.deg2rad(90.0 - a))


def direction_deg(theta_deg, phi_deg) -> np.ndarray:
    """ω = (sinθ cosφ, sinθ sinφ, cosθ) from angles in degrees."""
    st, ct = _sin_cos_deg(theta_deg)
    sp, cp = _sin_cos_deg(phi_deg)
    st, ct, sp, cp = np.broadcast_arrays(st, ct, sp, cp)
    return np.stack([st * cp, st * sp, ct], axis=-1)


def dot(a, b) -> np.ndarray:
    return np.einsum("...i,...i->...", a, b)


def half_vector(l, v):
    """h = (l+v)/‖l+v‖ and a mask of where it exists (l ≠ −v); h = 0 where it does not."""
    s = np.asarray(l, dtype=float) + np.asarray(v, dtype=float)
    norm = np.sqrt(dot(s, s))
    # Two unit vectors sum to length < 1e-12 only if they are opposite to within 1e-12
    # rad; there h is undefined and the specular term is 0.
    exists = norm > HALF_VECTOR_MIN_NORM
    inv = where_valid(exists, [norm], lambda n: 1.0 / n, 0.0)
    return s * inv[..., None], exists


# Below this, |l + v| is rounding noise of two opposite unit vectors (eps ≈ 2.2e-16 per
# component); the half vector is then undefined.
HALF_VECTOR_MIN_NORM = 1e-12


def reflect(v, m):
    """Mirror v about m: l = 2 (v·m) m − v."""
    return 2.0 * dot(v, m)[..., None] * m - v


def unit(x) -> np.ndarray:
    """x / ‖x‖ along the last axis (x ≠ 0)."""
    x = np.asarray(x, dtype=float)
    return x / np.sqrt(dot(x, x))[..., None]


def slopes_to_normal(X, Y) -> np.ndarray:
    """m ∝ (−X, −Y, 1) for slopes (X, Y) (Heitz 2014, eq. 2)."""
    return unit(np.stack([-X, -Y, np.ones_like(X)], axis=-1))
