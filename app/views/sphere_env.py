"""A sphere of any model under a point light or a procedural environment, in colour
(app/environment/: multiple importance sampling, its samples and noise stated)."""
from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from ..config import Settings
from ..environment.display import sphere_figure
from ..environment.maps import ENVIRONMENTS
from ..environment.render import render, render_point
from ..errors import ParameterError
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
    n: Annotated[int, Field(ge=8, le=512, description="pixels across the sphere (n×n image)")] = 128
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
    if q.environment == "point":
        return render_point(spec.brdf(), q.theta_i_deg, q.phi_i_deg, q.n, colour)
    return render(spec.brdf(), q.environment, q.theta_i_deg, q.phi_i_deg, q.n, q.samples, colour, q.seed)


def figure(data, spec, q) -> dict:
    label = "a point light" if q.environment == "point" else ENVIRONMENTS[q.environment].label
    return sphere_figure(data, q.exposure, f"Sphere under {label}")


VIEW = View(
    "sphere_env", "Sphere under an environment",
    "Any model on a sphere, in colour, under a point light or a procedural environment "
    "(sampled; the noise is stated).",
    SphereEnvQuery, SphereEnvFigureQuery, compute, figure, limits,
    roles={"environment": "geometry", "light_color": "geometry"},
    heavy=True)
