"""The roughness conventions of rendering ecosystems: ``GET /api/v1/conventions`` (the α
each means by one roughness value), its figure, and ``/conventions/check`` (the albedo
error of a model whose D and G use different α). The work is in app/shader/conventions."""
from __future__ import annotations

from typing import Annotated

import numpy as np
from fastapi import APIRouter, Query, Response
from pydantic import Field

from ... import figures
from ...errors import ParameterError
from ...figures.conventions import conventions_figure
from ...quantities import conventions_lobes
from ...shader import conventions
from ...views import schemas
from ..deps import Route
from ..encode import json_response
from ..query_rules import one_isotropic_lobe

router = APIRouter(prefix="/api/v1", route_class=Route)


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
    r, a = _unit("roughness", roughness), _unit("anisotropy", anisotropy)
    figure = conventions_figure(conventions_lobes(r, a), r, a)
    return Response(figures.to_json(figure), media_type="application/json")


class ConsistencyQuery(schemas.ModelQuery):
    alpha_G: Annotated[float, Field(ge=1e-4, le=1.0, description="the α the model's G (masking) was "
                                    "evaluated with, [1e-4, 1]; D uses the model's alpha")]
    n: Annotated[int, Field(ge=2, le=65, description="μ_k = k/(n−1), k = 0..n−1")] = 17

    def check(self) -> None:
        """The rules the schema cannot state (before any work): one isotropic lobe, no
        compensation. The fuzz test's oracle calls this too."""
        one_isotropic_lobe(self, "the check", compensation=True)


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


