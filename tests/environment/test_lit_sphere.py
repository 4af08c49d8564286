"""The one lit-sphere renderer (app/environment/sphere.py): a point light and the same
delta inside an environment give the closed-form radiance, through the renderer and
through both sphere views (their pipeline, without HTTP: each test well under 2 s)."""
from __future__ import annotations

import math

import numpy as np
import pytest

from app.environment.maps import ENVIRONMENTS
from app.environment.sphere import Lighting, lit_sphere, point_light
from app.config import Settings
from app.model import make_spec
from app.physics.vectors import direction_deg
from app.views import VIEWS, run

THETA, PHI, N = 50.0, 30.0, 20


def _pixels(n):
    c = -1.0 + (2.0 * np.arange(n) + 1.0) / n
    y, x = np.meshgrid(c[::-1], c, indexing="ij")
    return x, y, x * x + y * y < 1.0


def _lambert(kd, n):
    """L_o/E = (k_d/π) max(n·l, 0) at the pixel centres, n = (x, y, √(1−x²−y²))."""
    x, y, on = _pixels(n)
    l = direction_deg(THETA, PHI)
    z = np.sqrt(np.where(on, 1.0 - x * x - y * y, 0.0))
    return np.where(on, kd / math.pi * np.maximum(x * l[0] + y * l[1] + z * l[2], 0.0), np.nan)


def _ggx_at(x, y, alpha):
    """GGX with height-correlated Smith G2 and F = 1 at one pixel, from Walter et al.
    2007 eq. 33 (D) and Heitz 2014 eq. 99 (G2), in the pixel's normal frame: the angles
    alone (the model is isotropic)."""
    n = np.array([x, y, math.sqrt(1.0 - x * x - y * y)])
    l, v = direction_deg(THETA, PHI), np.array([0.0, 0.0, 1.0])
    h = (l + v) / np.linalg.norm(l + v)
    mu_l, mu_v, mu_h = n @ l, n @ v, n @ h
    D = alpha ** 2 / (math.pi * (mu_h ** 2 * (alpha ** 2 - 1.0) + 1.0) ** 2)

    def lam(mu):
        return (-1.0 + math.sqrt(1.0 + alpha ** 2 * (1.0 - mu * mu) / (mu * mu))) / 2.0
    return D / (1.0 + lam(mu_l) + lam(mu_v)) / (4.0 * mu_l * mu_v) * mu_l


def test_point_light_and_one_delta_in_an_environment_are_the_closed_form():
    """A Lambertian sphere: the point light (grey, E = 1), the point light in colour and
    the same delta added to a black environment (uniform, colour 0) each give
    (k_d/π)·max(n·l, 0)·E per pixel."""
    brdf = make_spec(kd=0.6, f0=0.0, f90=0.0).brdf()
    expected = _lambert(0.6, N)
    grey = lit_sphere(brdf, point_light(THETA, PHI), N, rgb=False)["radiance"]
    np.testing.assert_allclose(grey, expected, rtol=1e-12, atol=1e-15)
    E = np.array([1.0, 0.5, 0.25])
    colour = lit_sphere(brdf, point_light(THETA, PHI, E), N)["radiance"]
    np.testing.assert_allclose(colour, expected[..., None] * E, rtol=1e-12, atol=1e-15)
    delta = point_light(THETA, PHI, E).deltas
    dark = Lighting(ENVIRONMENTS["uniform"], colour=np.zeros(3), deltas=delta)
    mixed = lit_sphere(brdf, dark, N, samples=4)
    np.testing.assert_allclose(mixed["radiance"], expected[..., None] * E, rtol=1e-12, atol=1e-15)
    assert mixed["noise"]["relative"] == 0.0 and np.all(mixed["background"] == 0.0)


def _view(name: str, **params) -> dict:
    """The arrays of a view for a query, through the pipeline the routes use."""
    view = VIEWS[name]
    return run(view, view.figure_query(**params), Settings()).data


def test_the_two_sphere_views_draw_the_same_point_lit_sphere():
    """``sphere`` (L_o/E) and ``sphere_env`` at environment=point (E = π·colour) agree
    pixel by pixel with each other and with GGX's formula at a pixel off the highlight."""
    query = {"alpha": 0.4, "fresnel": "none", "theta_i_deg": THETA, "phi_i_deg": PHI, "n": N}
    grey = _view("sphere", **query)["radiance"]
    rgb = _view("sphere_env", environment="point", **query)["radiance"]
    np.testing.assert_allclose(rgb, np.repeat(grey[..., None], 3, axis=-1) * math.pi, rtol=1e-12, atol=1e-15)
    x, y, _ = _pixels(N)
    i, j = 13, 6                                          # lit, far from the mirror point
    assert grey[i, j] == pytest.approx(_ggx_at(x[i, j], y[i, j], 0.4), rel=1e-9)
