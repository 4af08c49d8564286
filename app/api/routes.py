"""Routes of API v1 that are not figures: health, the model registry, /eval, and each
view's data route. Each parses, calls the views' pipeline or one computation, encodes."""
from typing import Annotated

import numpy as np
from fastapi import APIRouter, Body, HTTPException, Query, Request, Response

from .. import __version__, quantities
from ..errors import ParameterError
from ..model import COMMON_PARAMS, OPTIONAL_PARAMS, OPTIONS, SUB_OPTIONS, choice_params
from ..views import VIEWS, View, lookup, run, schemas
from .encode import json_response
from .http.query_route import QueryModelRoute
from .openapi import operations

router = APIRouter(prefix="/api/v1", route_class=QueryModelRoute)

GEOMETRY = [
    {"name": "theta_i_deg", "label": "θ_i (incidence, degrees)", "lo": 0.0, "hi": 90.0,
     "default": 45.0, "description": "Polar angle of the light direction l.", "lo_open": False,
     "scale": "linear", "unit": "°"},
    {"name": "phi_i_deg", "label": "φ_i (azimuth, degrees)", "lo": -360.0, "hi": 360.0,
     "default": 0.0, "description": "Azimuth of l from the tangent x (direction of α_x).",
     "lo_open": False, "scale": "linear", "unit": "°"},
]


@router.get("/health", tags=["meta"], summary="Liveness and version",
            responses={200: {"content": {"application/json": {"example": {"status": "ok", "version": "0.1.0"}}}}})
def health():
    return {"status": "ok", "version": __version__}


def _choice(option: str, name: str, entry) -> dict:
    out = {"name": name, "label": entry.label, "description": entry.description,
           "params": [p.as_dict() for p in choice_params(option, name)]}
    for attr in ("reference", "applies_to", "anisotropic", "isotropic_only", "needs_phi",
                 "approximation", "derived_doc"):
        if hasattr(entry, attr):
            out[attr] = getattr(entry, attr)
    return out


@router.get("/models", tags=["meta"], summary="Every option with its parameters, ranges and defaults",
            responses={200: {"content": {"application/json": {"example": {
                "version": "0.1.0",
                "params": [{"name": "alpha", "label": "α (roughness, x)", "lo": 0.0001, "hi": 1.0,
                            "default": 0.3, "scale": "log", "unit": ""}],
                "geometry": [{"name": "theta_i_deg", "lo": 0.0, "hi": 90.0, "default": 45.0, "unit": "°"}],
                "options": {"ndf": {"label": "Normal distribution D", "default": "ggx",
                                    "choices": [{"name": "ggx", "label": "GGX (Trowbridge-Reitz)",
                                                 "params": []}]}}}}}}})
def models():
    return {
        "version": __version__,
        "params": [{**p.as_dict(), "optional": p.name in OPTIONAL_PARAMS} for p in COMMON_PARAMS],
        "geometry": GEOMETRY,
        "options": {
            option: {"label": label, "default": default,
                     "choices": [_choice(option, name, entry) for name, entry in registry.items()]}
            for option, (label, registry, default) in OPTIONS.items()
        },
        "sub_options": {
            name: {"label": label, "default": default, "applies_with": when,
                   "choices": [{"name": key, "label": entry.label, "description": entry.description}
                               for key, entry in registry.items()]}
            for name, (label, registry, default, _, when) in SUB_OPTIONS.items()
        },
    }


def _evaluate(q: schemas.EvalQuery, limit: int, status: int, env: str):
    lists = {name: getattr(q, name) for name in ("theta_i_deg", "phi_i_deg", "theta_o_deg", "phi_o_deg")}
    sizes = {name: len(v) for name, v in lists.items()}
    for name, size in sizes.items():
        if size == 0:
            raise ParameterError(name, f"{name} is empty: give at least one value")
        if size > limit:
            raise ParameterError(name, f"{name} has {size} values; the limit is {limit} (setting {env})",
                             status=status)
    n = max(sizes.values())
    for name, size in sizes.items():
        if size not in (1, n):
            raise ParameterError(name, f"{name} has {size} values but another list has {n}: "
                                   "lists must have equal length, or one value to broadcast")
    spec = schemas.spec_of(q)
    arrays = {k: np.asarray(v, dtype=float) for k, v in lists.items()}
    return json_response(quantities.evaluate(
        spec.brdf(), arrays["theta_i_deg"], arrays["phi_i_deg"],
        arrays["theta_o_deg"], arrays["phi_o_deg"], tuple(dict.fromkeys(q.quantities))))


@router.get("/eval", tags=["data"], summary="BRDF terms at direction pairs (i = light l, o = view v)",
            description="f, D(h), G1(l,h), G1(v,h), G2, F(v·h). A divergence (f where both "
                        "directions graze) is null.")
def eval_get(request: Request, q: Annotated[schemas.EvalQuery, Query()]):
    s = request.app.state.settings
    return _evaluate(q, s.max_query_list, 422, "BRDF_MAX_QUERY_LIST")


@router.post("/eval", tags=["data"], summary="BRDF terms for a large batch, as a JSON body")
def eval_post(request: Request, q: Annotated[schemas.EvalQuery, Body(openapi_examples={
        "two pairs": {"summary": "GGX α=0.2, two direction pairs",
                      "value": {"ndf": "ggx", "alpha": 0.2, "theta_i_deg": [30, 60], "phi_i_deg": [0],
                                "theta_o_deg": [30, 60], "phi_o_deg": [180], "quantities": ["f", "D"]}}})]):
    s = request.app.state.settings
    return _evaluate(q, s.max_batch, 413, "BRDF_MAX_BATCH")


def _data_route(view: View):
    def route(request: Request, q: Annotated[view.query, Query()]) -> Response:
        return json_response(run(view, q, request.app.state.settings).data)
    return route


for _view in VIEWS.values():
    router.add_api_route(f"/{_view.name}", _data_route(_view), methods=["GET"], tags=["data"],
                         summary=f"{_view.title}: {_view.summary}", name=f"data_{_view.name}")


#: Included last (app/main.py): any other /api/v1 path is a 404 that lists the views.
fallback = APIRouter(prefix="/api/v1", route_class=QueryModelRoute)


@fallback.api_route("/{name}", methods=["GET", "POST"], include_in_schema=False)
def unknown(request: Request, name: str):
    """A path that exists with other methods is a 405 naming them (POST /api/v1/health);
    an unknown name is a 404 listing the views; a view's data route takes GET only."""
    path = f"/api/v1/{name}"
    item = operations(request.app).exact.get(path, {})     # the routes' index, built once
    allowed = sorted(m.upper() for m in item if m in ("get", "post", "put", "delete"))
    if not allowed:
        lookup(name)
        allowed = ["GET"]
    raise HTTPException(405, "Method Not Allowed", headers={"Allow": ", ".join(allowed)})
