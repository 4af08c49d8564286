"""Brute-force references for the environment sphere: directions uniform on the whole
sphere and the environment's radiance along them, independent of its sampling."""
from __future__ import annotations

import numpy as np

from app.environment.maps import ENVIRONMENTS
from app.environment.sphere import environment_lighting, lit_sphere
from app.physics.vectors import direction_deg


def uniform_radiance(environment: str, theta_deg: float, phi_deg: float, n: int, seed: int):
    """(w (n, 3) uniform unit vectors, L (n,) the red channel of a white environment's
    radiance along them); a mean over w of g(w) · 4π estimates ∫ g dω."""
    w = np.random.default_rng(seed).normal(size=(n, 3))
    w /= np.linalg.norm(w, axis=1, keepdims=True)
    L = ENVIRONMENTS[environment].radiance(w, direction_deg(theta_deg, phi_deg), np.ones(3))[:, 0]
    return w, L


def render(brdf, environment: str, theta_deg: float, phi_deg: float, n: int, samples: int,
           colour=(1.0, 1.0, 1.0), seed: int = 0) -> dict:
    """The lit sphere (app/environment/sphere.py) under the procedural ``environment``."""
    return lit_sphere(brdf, environment_lighting(environment, theta_deg, phi_deg, colour), n,
                      samples=samples, seed=seed)
