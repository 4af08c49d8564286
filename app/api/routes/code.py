"""``GET /api/v1/code``: the configured model as self-contained GLSL, HLSL or Python (the
work is in app/shader)."""
from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Response
from pydantic import Field

from ...model import make_spec
from ...shader.dsl import LANGS
from ...model.registry import families
from ...shader.generate import describe, generate, writes
from ...views import schemas
from ..deps import Route
from ..encode import json_response

router = APIRouter(prefix="/api/v1", tags=["code"], route_class=Route)

EXTENSIONS = {"glsl": "glsl", "hlsl": "hlsl", "python": "py"}


#: The families /code writes (generate.writes; /models says ``shader``).
WRITTEN = tuple(name for name, family in families().items() if writes(family))


class CodeQuery(schemas.ModelQuery):
    model: Annotated[Literal[WRITTEN], Field(
        description="the model families code generation writes: " + ", ".join(WRITTEN))] = "microfacet"
    lang: Annotated[Literal[LANGS], Field(
        description="glsl: GLSL ES 3.00 (WebGL2), `vec3 brdf(vec3 n, vec3 l, vec3 v)`; hlsl: "
                    "`float3 brdf(float3 n, float3 l, float3 v)`; python: numpy, `brdf(n, l, v)` "
                    "over arrays (…, 3) → (…, 3)")] = "glsl"
    form: Annotated[Literal["const", "uniform"], Field(
        description="const: the material's parameters baked in as constants (a snapshot); "
                    "uniform: α_x, α_y, shape, F₀/F₉₀ or η/κ per channel, k_d and the diffuse "
                    "parameters as uniforms (model=principled: base colour, roughness, metallic, … "
                    "as uniforms, everything derived formed in the shader), so one compiled shader "
                    "draws any material")] = "const"
    format: Annotated[Literal["text", "json"], Field(
        description="text: the code alone; json: the code with its uniforms and their values, "
                    "what stays baked and why, each approximation with its stated maximum "
                    "error, the data texture a Kulla-Conty shader reads (textures), the uniform "
                    "block a parameterised shader reads its Smith fits from (blocks), the "
                    "precision notes and the line count")] = "text"


@router.get("/code", summary="The configured model as self-contained GLSL, HLSL or Python",
            description="A function brdf(n, l, v) returning f as RGB (no cosine), with the helpers "
                        "D, G1, G2, F, each generated from the registry entry's one formula; where "
                        "Smith's Λ has no closed form, a Chebyshev fit with its stated maximum error; "
                        "Kulla-Conty's E as the cubic pieces of the lobe's E(μ) at its α — in GLSL and "
                        "HLSL read, with the Smith fit, from one R32F data texture BRDF_DATA "
                        "(unfiltered; its values in the JSON's textures); in form=uniform without "
                        "Kulla-Conty, from one std140 uniform block BRDF_TABLES (the JSON's blocks). A model "
                        "entry without a shader form is a 422 naming it. Plain text, or JSON with "
                        "format=json.",
            responses={200: {"content": {"text/plain": {"example": "vec3 brdf(vec3 n, vec3 l, vec3 v) {…}"}}}})
def code(q: Annotated[CodeQuery, Query()]) -> Response:
    spec = make_spec(**schemas.model_values(q))
    if q.format == "json":
        return json_response(describe(spec, q.lang, q.form))
    return Response(generate(spec, q.lang, q.form), media_type="text/plain; charset=utf-8",
                    headers={"Content-Disposition": f'inline; filename="brdf.{EXTENSIONS[q.lang]}"'})


