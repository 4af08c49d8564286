"""Routes for shader writers: the model as code (more follow: LUTs, conventions, materials).

Each takes the model parameters every endpoint takes (schemas.ModelQuery).
"""
from __future__ import annotations

from typing import Annotated, Literal

import numpy as np

from fastapi import APIRouter, Query, Response
from pydantic import Field

from .. import figures, materials
from ..integrate.albedo import albedo_average
from ..errors import ParameterError
from ..model import make_spec
from ..shader import conventions
from ..shader.conventions_figure import conventions_figure
from ..shader.dsl import LANGS
from ..shader.generate import generate
from ..views import schemas
from .encode import json_response
from .http.query_route import QueryModelRoute

router = APIRouter(prefix="/api/v1", route_class=QueryModelRoute)

EXTENSIONS = {"glsl": "glsl", "hlsl": "hlsl", "python": "py"}


class CodeQuery(schemas.ModelQuery):
    model: Annotated[Literal["microfacet"], Field(
        description="code generation writes the microfacet model (the options above) only")] = "microfacet"
    diffuse: Annotated[Literal["lambert"], Field(
        description="code generation writes the diffuse term as Lambert's kd/π only")] = "lambert"
    lang: Annotated[Literal[LANGS], Field(
        description="glsl: GLSL ES 3.00 (WebGL2), `vec3 brdf(vec3 n, vec3 l, vec3 v)`; hlsl: "
                    "`float3 brdf(float3 n, float3 l, float3 v)`; python: numpy, `brdf(n, l, v)` "
                    "over arrays (…, 3) → (…, 3)")] = "glsl"


@router.get("/code", tags=["code"], summary="The configured model as self-contained GLSL, HLSL or Python",
            description="A function brdf(n, l, v) returning f as RGB (no cosine), with the helpers "
                        "D, G1, G2, F; tables (Smith Λ without closed form, Kulla-Conty E) embedded "
                        "as arrays. Plain text.",
            responses={200: {"content": {"text/plain": {"example": "vec3 brdf(vec3 n, vec3 l, vec3 v) {…}"}}}})
def code(q: Annotated[CodeQuery, Query()]) -> Response:
    spec = make_spec(**schemas.model_values(q))
    return Response(generate(spec, q.lang), media_type="text/plain; charset=utf-8",
                    headers={"Content-Disposition": f'inline; filename="brdf.{EXTENSIONS[q.lang]}"'})


# Checked here rather than by the schema: the model's own `roughness` is [0.01, 1], and the
# shared validation message would name that range; an engine's roughness may be 0.
Roughness = Annotated[float, Field(description="the roughness value an artist typed, [0, 1]", examples=[0.5])]
Anisotropy = Annotated[float, Field(description="anisotropy, [0, 1] (the maps that have one)")]


def _unit(name: str, x: float) -> float:
    if not 0.0 <= x <= 1.0:
        raise ParameterError(name, f"{name} must be a number in [0, 1]; got {x!r}")
    return x


@router.get("/conventions", tags=["code"], summary="The α each ecosystem means by one roughness value",
            description="[{ecosystem, alpha, alpha_y, note, (k)}]: Disney, glTF, Filament, UE4 (D, and the "
                        "Schlick-GGX k of its G for direct and image-based light), pbrt-v3, pbrt-v4, Blender "
                        "Principled, OpenPBR; α as that engine computes it, even outside [1e-4, 1] (said in "
                        "the note).")
def conventions_route(roughness: Roughness = 0.5, anisotropy: Anisotropy = 0.0) -> Response:
    return json_response(conventions.table(_unit("roughness", roughness), _unit("anisotropy", anisotropy)))


@router.get("/conventions/figure", tags=["figures"], summary="Plotly figure: the α of each ecosystem and its lobe")
def conventions_figure_route(roughness: Roughness = 0.5, anisotropy: Anisotropy = 0.0) -> Response:
    figure = conventions_figure(_unit("roughness", roughness), _unit("anisotropy", anisotropy))
    return Response(figures.to_json(figure), media_type="application/json")


class ConsistencyQuery(schemas.ModelQuery):
    alpha_G: Annotated[float, Field(ge=1e-4, le=1.0, description="the α the model's G (masking) was "
                                    "evaluated with, [1e-4, 1]; D uses the model's alpha")]
    n: Annotated[int, Field(ge=2, le=65, description="μ_k = k/(n−1), k = 0..n−1")] = 17

    def check(self) -> None:
        """The rules the schema cannot state (before any work): one isotropic lobe, no
        compensation. The fuzz test's oracle calls this too."""
        _one_isotropic_lobe(self, "the check", compensation=True)


def _one_isotropic_lobe(q: schemas.ModelQuery, what: str, compensation: bool) -> None:
    """Refuse, naming the parameter that makes it so, a model with anisotropic roughness,
    a weighted second lobe or (``compensation``) multiple-scattering compensation."""
    brdf = schemas.spec_of(q).brdf()
    given = q.model_fields_set
    if not brdf.ndf.isotropic:
        param = next((p for p in ("alpha_y", "anisotropy") if p in given), "alpha_y")
        raise ParameterError(param, f"{what} is for isotropic roughness (no alpha_y or anisotropy)")
    if brdf.lobe2 is not None and brdf.lobe_mix > 0:
        raise ParameterError("lobe_mix", f"{what} is for one lobe (lobe_mix = 0)")
    if compensation and getattr(brdf, "multiscatter", None) is not None:
        raise ParameterError("multiscatter", f"{what} is for single scattering (multiscatter=none)")


@router.get("/conventions/check", tags=["code"], summary="A model whose D and G use different α: the albedo error",
            description="The bug class of mixed conventions (D at α = r², G at another α): E(μ) and E_avg "
                        "with G at alpha_G against the consistent model, F as configured.")
def conventions_check(q: Annotated[ConsistencyQuery, Query()]) -> Response:
    q.check()
    brdf = schemas.spec_of(q).brdf()
    mu = np.linspace(0.0, 1.0, q.n)
    out = conventions.consistency(brdf, q.alpha_G, mu)
    out["flag"] = None if out["consistent"] else (
        f"D uses α = {out['alpha_D']:.4g} but G uses α = {q.alpha_G:.4g}: E_avg changes by "
        f"{out['E_avg_difference']:+.3g} (E by up to {out['max_E_difference']:.3g})")
    return json_response(out)


@router.get("/materials", tags=["code"], summary="Measured materials: RGB complex index of metals, index of dielectrics",
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
        _one_isotropic_lobe(self, "the E_avg comparison", compensation=False)


@router.get("/materials/fresnel", tags=["code"],
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


@router.get("/materials/sphere", tags=["code"], summary="A lit sphere in colour (RGB f of a material)",
            description="L_o/E = f_rgb cos θ_l per pixel under a distant light, sRGB-encoded 0–255, values above 1 "
                        "clipped (max before clipping given). With no material the three channels are equal.",
            responses={200: {"content": {"application/json": {"example": {"rgb": [[[255, 255, 255]]], "max": 0.8}}}}})
def material_sphere_route(q: Annotated[MaterialSphereQuery, Query()]) -> Response:
    spec = make_spec(**schemas.model_values(q))
    return json_response(materials.lit_sphere(spec.brdf(), q.theta_i_deg, q.n))
