"""The principled BRDF's own views and the environment-lit sphere:

GET /api/v1/principled               its parameters, ranges, defaults and options
GET /api/v1/principled/albedo        E(μ) per lobe and channel (stacked chart's data)
GET /api/v1/figures/principled_albedo  the stacked albedo chart
GET /api/v1/sphere_env               the sphere of any model under a point light or an
GET /api/v1/figures/sphere_env       environment, in colour (data / PNG figure)
"""
from __future__ import annotations

from typing import Annotated, Literal

import numpy as np
from fastapi import APIRouter, Query, Request
from pydantic import Field
from starlette.concurrency import run_in_threadpool

from ..environment.display import sphere_figure
from ..environment.maps import ENVIRONMENTS
from ..environment.render import render, render_point
from ..errors import ParameterError
from ..model import make_spec
from ..principled.params import BASE_COLOR_DEFAULT, OPTIONS, PARAMS
from ..principled.spec import ROUGHNESS, parse_color
from ..views import schemas
from .encode import json_response

router = APIRouter(prefix="/api/v1")


@router.get("/principled", tags=["meta"], summary="The principled BRDF's parameters and options",
            responses={200: {"content": {"application/json": {"example": {
                "base_color": {"default": [0.82, 0.67, 0.16], "lo": 0.0, "hi": 1.0},
                "params": [{"name": "metallic", "lo": 0.0, "hi": 1.0, "default": 0.0}],
                "options": {"lobe": {"label": "Lobe shown", "default": "all", "choices": []}},
                "reference": "Burley 2012"}}}}})
def principled_catalogue():
    return {"base_color": {"default": list(BASE_COLOR_DEFAULT), "lo": 0.0, "hi": 1.0},
            "params": [ROUGHNESS.as_dict()] + [p.as_dict() for p in PARAMS],
            "options": {name: {"label": label, "default": default,
                               "choices": [{"name": c.name, "label": c.label, "description": c.description}
                                           for c in choices.values()]}
                        for name, (label, choices, default) in OPTIONS.items()},
            "reference": "Burley 2012, Physically-Based Shading at Disney; docs/principled.md"}


class PrincipledAlbedoQuery(schemas.ModelQuery):
    n: Annotated[int, Field(ge=2, le=91, description="view angles θ_v = 0..90°, both ends")] = 19


def _principled_albedo(q: PrincipledAlbedoQuery) -> dict:
    spec = make_spec(**{**schemas.model_values(q), "model": "principled"})
    mu = np.cos(np.radians(np.linspace(0.0, 90.0, q.n)))
    return spec.brdf().albedo_by(mu)


@router.get("/principled/albedo", tags=["data"], summary="Directional albedo of each principled lobe")
async def principled_albedo(q: Annotated[PrincipledAlbedoQuery, Query()]):
    return json_response(await run_in_threadpool(_principled_albedo, q))


@router.get("/figures/principled_albedo", tags=["figures"], summary="Stacked albedo of the principled lobes")
async def principled_albedo_figure(q: Annotated[PrincipledAlbedoQuery, Query()]):
    from ..principled.figure import stacked_albedo_figure
    data = await run_in_threadpool(_principled_albedo, q)
    return json_response(stacked_albedo_figure(data, "Principled BRDF: albedo by lobe"))


class SphereEnvQuery(schemas.ModelQuery):
    environment: Annotated[Literal[("point", *ENVIRONMENTS)], Field(
        description="point: one directional light; uniform (white furnace), studio (two soft boxes), "
                    "overcast, sunset: procedural environments")] = "studio"
    theta_i_deg: Annotated[float, Field(ge=0.0, le=90.0, description="light direction from the view, degrees")] = 40.0
    phi_i_deg: Annotated[float, Field(ge=-360.0, le=360.0, description="its azimuth in the image, degrees")] = 135.0
    n: Annotated[int, Field(ge=8, le=512, description="pixels per side")] = 256
    samples: Annotated[int, Field(ge=4, le=256, description="samples per pixel (environments)")] = 16
    seed: Annotated[int, Field(ge=0, le=2**31 - 1)] = 0
    exposure: Annotated[float, Field(ge=-10.0, le=10.0, description="exposure in EV (×2^EV)")] = 0.0
    light_color: Annotated[str, Field(description="light / environment colour r,g,b in [0, 1]",
                                      examples=["1,1,1"])] = "1,1,1"


def _sphere(q: SphereEnvQuery, settings) -> dict:
    work = q.n * q.n * (1 if q.environment == "point" else q.samples)
    if work > settings.max_grid_points * 64:
        raise ParameterError("samples", f"n²×samples = {work} exceeds {settings.max_grid_points * 64} "
                                        "(BRDF_MAX_GRID_POINTS × 64)", status=413)
    try:
        colour = parse_color(q.light_color)
    except ParameterError as exc:
        raise ParameterError("light_color", exc.message.replace("base_color", "light_color")) from exc
    brdf = make_spec(**schemas.model_values(q)).brdf()
    if q.environment == "point":
        return render_point(brdf, q.theta_i_deg, q.phi_i_deg, q.n, colour)
    return render(brdf, q.environment, q.theta_i_deg, q.phi_i_deg, q.n, q.samples, colour, q.seed)


@router.get("/sphere_env", tags=["data"], summary="A sphere of the model under a light or an environment")
async def sphere_env(request: Request, q: Annotated[SphereEnvQuery, Query()]):
    data = await run_in_threadpool(_sphere, q, request.app.state.settings)
    return json_response({**data, "radiance": np.where(np.isnan(data["radiance"]), None, data["radiance"]).tolist()})


@router.get("/figures/sphere_env", tags=["figures"], summary="The lit sphere in colour (PNG in a figure)")
async def sphere_env_figure(request: Request, q: Annotated[SphereEnvQuery, Query()]):
    data = await run_in_threadpool(_sphere, q, request.app.state.settings)
    title = f"Sphere under {ENVIRONMENTS[q.environment].label if q.environment != 'point' else 'a point light'}"
    return json_response(sphere_figure(data, q.exposure, title))
