"""``GET /api/v1/code``: the configured model as self-contained GLSL, HLSL or Python (the
work is in app/shader)."""
from __future__ import annotations

from typing import Annotated, Literal

from fastapi import APIRouter, Query, Response
from pydantic import Field

from ...model import make_spec
from ...shader.dsl import LANGS
from ...shader.generate import generate
from ...views import schemas
from ..deps import Route

router = APIRouter(prefix="/api/v1", tags=["code"], route_class=Route)

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


@router.get("/code", summary="The configured model as self-contained GLSL, HLSL or Python",
            description="A function brdf(n, l, v) returning f as RGB (no cosine), with the helpers "
                        "D, G1, G2, F; tables (Smith Λ without closed form, Kulla-Conty E) embedded "
                        "as arrays. Plain text.",
            responses={200: {"content": {"text/plain": {"example": "vec3 brdf(vec3 n, vec3 l, vec3 v) {…}"}}}})
def code(q: Annotated[CodeQuery, Query()]) -> Response:
    spec = make_spec(**schemas.model_values(q))
    return Response(generate(spec, q.lang), media_type="text/plain; charset=utf-8",
                    headers={"Content-Disposition": f'inline; filename="brdf.{EXTENSIONS[q.lang]}"'})


