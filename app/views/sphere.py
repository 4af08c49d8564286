"""A sphere lit by one directional light."""
from __future__ import annotations

from ..environment.sphere import lit_sphere, point_light
from ..figures.images import lit_sphere_figure
from . import schemas
from .view import View, square_grid_limits

VIEW = View(
    "sphere", "Lit sphere",
    "A sphere under one directional light: L_o/E = f·cos θ_l per pixel (rows y, "
    "columns x; null off the sphere).",
    schemas.SphereQuery, schemas.SphereFigureQuery,
    lambda spec, q: lit_sphere(spec.brdf(), point_light(q.theta_i_deg, q.phi_i_deg), q.n, rgb=False),
    lambda data, spec, q: lit_sphere_figure(data, spec.values, q.theta_i_deg, q.phi_i_deg,
                                            q.display, q.exposure),
    square_grid_limits,
    heavy=True)
