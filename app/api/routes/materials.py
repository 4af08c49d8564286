"""Measured materials (physicallybased.info, CC0): ``GET /api/v1/materials``, a material's
exact RGB Fresnel beside its approximations (``/materials/fresnel``) and a lit sphere in
its colour (``/materials/sphere``). The work is in app/materials.py."""
from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Response
from pydantic import Field

from ... import materials
from ...environment.sphere import lit_sphere, point_light
from ...figures.sphere_image import srgb8_sphere
from ...integrate.albedo import albedo_average
from ...model import make_spec
from ...views import schemas
from ..deps import Route
from ..encode import json_response
from ..query_rules import one_isotropic_lobe

router = APIRouter(prefix="/api/v1", tags=["code"], route_class=Route)


@router.get("/materials", summary="Measured materials: RGB complex index of metals, index of dielectrics",
            responses={200: {"content": {"application/json": {"example": {
                "source": "physicallybased.info …", "license": "CC0 1.0 Universal …",
                "materials": [{"name": "Gold", "slug": "gold", "kind": "conductor", "n": [0, 0.3516, 1.8589],
                               "k": [6.594, 2.0814, 1.4963], "f0": [1.0, 0.7887, 0.4286]}]}}}}},
            description="physicallybased.info (CC0): name, slug (the value of `material`), kind, n and k per linear-sRGB "
                        "channel (conductors) or ior (dielectrics), F₀ per channel, F82 and edge tints.")
def materials_route() -> Response:
    return json_response(materials.listing())


class MaterialFresnelQuery(schemas.ModelQuery):
    material: Annotated[Literal[tuple(materials.materials())], Field(
        examples=["gold"], description="the measured material (GET /api/v1/materials lists them)")]
    n: Annotated[int, Field(ge=2, le=721, description="angles θ = 0..90°, both ends")] = 91

    def check(self) -> None:
        """The E_avg comparison is for isotropic roughness (before any work)."""
        one_isotropic_lobe(self, "the E_avg comparison", compensation=False)


@router.get("/materials/fresnel",
            summary="A material's exact RGB Fresnel beside Schlick, F82-tint and Gulbrandsen, with their errors",
            description="Per channel: F(θ) of each form, its error against the exact one, and E_avg of the "
                        "configured model's lobe with each form (adaptive quadrature; bounds given).")
def material_fresnel_route(q: Annotated[MaterialFresnelQuery, Query()]) -> Response:
    q.check()
    brdf = schemas.spec_of(q).brdf()
    lobe = brdf.single() if hasattr(brdf, "single") else brdf
    return json_response(materials.comparison(q.material, lobe.lobes()[0][1], q.n,
                                              lambda b: albedo_average(b, tol=1e-5)))


class MaterialSphereQuery(schemas.ModelQuery):
    theta_i_deg: Annotated[float, Field(ge=0.0, le=90.0, description="angle between light and viewer, degrees")] = 45.0
    n: Annotated[int, Field(ge=8, le=256, description="pixels across (n × n)")] = 128


@router.get("/materials/sphere", summary="A lit sphere in colour (RGB f of a material)",
            description="L_o/E = f_rgb cos θ_l per pixel under a distant light, sRGB-encoded 0–255, values above 1 "
                        "clipped (max before clipping given). With no material the three channels are equal.",
            responses={200: {"content": {"application/json": {"example": {"rgb": [[[255, 255, 255]]], "max": 0.8}}}}})
def material_sphere_route(q: Annotated[MaterialSphereQuery, Query()]) -> Response:
    spec = make_spec(**schemas.model_values(q))
    return json_response(srgb8_sphere(lit_sphere(spec.brdf(), point_light(q.theta_i_deg, 0.0), q.n)))
