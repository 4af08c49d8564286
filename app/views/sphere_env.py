"""A sphere of any model under a point light or a procedural environment, in colour,
over the environment behind it (app/environment/sphere.py: multiple importance sampling,
its samples and noise stated)."""
from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from pydantic import Field

from ..config import Settings
from ..environment.maps import ENVIRONMENTS
from ..environment.sphere import POINT_IRRADIANCE, environment_lighting, lit_sphere, point_light
from ..errors import ParameterError
from ..figures.sphere_image import environment_sphere_figure
from ..principled.colour import parse_color
from . import schemas
from .view import View


class SphereEnvQuery(schemas.ModelQuery):
    environment: Annotated[Literal[("point", *ENVIRONMENTS)], Field(
        description="point: one directional light; uniform (white furnace), studio (two soft boxes), "
                    "overcast, sunset: procedural environments")] = "studio"
    theta_i_deg: Annotated[schemas.Theta, Field(description="light direction (key box, zenith, sun): "
                                                            "angle from the viewer, degrees")] = 40.0
    phi_i_deg: Annotated[schemas.Phi, Field(description="its azimuth in the image plane from +x, "
                                                        "degrees")] = 135.0
    n: Annotated[int, Field(ge=8, le=512, description="pixels across the sphere (n×n image)")] = 256
    samples: Annotated[int, Field(ge=4, le=256, description="samples per pixel (environments)")] = 16
    seed: Annotated[int, Field(ge=0, le=2**31 - 1, description="random seed of the samples")] = 0
    light_color: Annotated[str, Field(description="light / environment colour r,g,b in [0, 1]",
                                      examples=["1,1,1"])] = "1,1,1"


class SphereEnvFigureQuery(SphereEnvQuery):
    exposure: Annotated[float, Field(ge=-10.0, le=10.0, description="exposure in EV (×2^EV)")] = 0.0


def limits(q, s: Settings) -> None:
    light_colour(q)                     # refused before any work
    work = q.n * q.n * (1 if q.environment == "point" else q.samples)
    if work > s.max_grid_points * 64:
        raise ParameterError("samples", f"n²×samples = {work} exceeds {s.max_grid_points * 64} "
                                        "(setting BRDF_MAX_GRID_POINTS × 64)", status=413)


def light_colour(q):
    """The light's r, g, b, or a ParameterError naming light_color."""
    try:
        return parse_color(q.light_color)
    except ParameterError as exc:
        raise ParameterError("light_color", exc.message.replace("base_color", "light_color")) from exc


def compute(spec, q) -> dict:
    colour = light_colour(q)
    lighting = (point_light(q.theta_i_deg, q.phi_i_deg, np.multiply(POINT_IRRADIANCE, colour)) if q.environment == "point"
                else environment_lighting(q.environment, q.theta_i_deg, q.phi_i_deg, colour))
    return lit_sphere(spec.brdf(), lighting, q.n, samples=q.samples, seed=q.seed)


def figure(data, spec, q) -> dict:
    label = "a point light" if q.environment == "point" else ENVIRONMENTS[q.environment].label
    return environment_sphere_figure(data, spec.values, label, q.exposure)


VIEW = View(
    "sphere_env", "Sphere under an environment",
    "Any model on a sphere, in colour, under a point light or a procedural environment "
    "(sampled; the noise is stated).",
    SphereEnvQuery, SphereEnvFigureQuery, compute, figure, limits,
    roles={"environment": "geometry", "light_color": "geometry"},
    heavy=True)
