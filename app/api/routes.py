"""Routes of API v1. Each parses, checks limits, calls one computation, encodes."""
from typing import Annotated, Any, Optional

import numpy as np
from fastapi import APIRouter, Body, Query, Request, Response
from pydantic import BaseModel, ConfigDict, Field, ValidationError

from .. import __version__, figures, quantities
from ..figures.overlay import overlay
from ..figures.style import model_title
from ..model import (COMMON_PARAMS, OPTIONAL_PARAMS, OPTIONS, SUB_OPTIONS, choice_params,
                     make_spec)
from ..physics.vectors import direction_deg
from . import schemas
from .encode import json_response
from ..errors import ParameterError
from .views import VIEWS, View

router = APIRouter(prefix="/api/v1")

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
    spec = make_spec(**schemas.model_values(q))
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
        view.check(q, request.app.state.settings)
        spec = make_spec(**schemas.model_values(q))
        return json_response(view.compute(spec, q))
    return route


def _figure_route(view: View):
    def route(request: Request, q: Annotated[view.figure_query, Query()]) -> Response:
        view.check(q, request.app.state.settings)
        spec = make_spec(**schemas.model_values(q))
        figure = view.figure(view.compute(spec, q), spec, q)
        return Response(figures.to_json(figure), media_type="application/json")
    return route


for _view in VIEWS.values():
    router.add_api_route(f"/{_view.name}", _data_route(_view), methods=["GET"], tags=["data"],
                         summary=_view.summary, name=f"data_{_view.name}")
    router.add_api_route(f"/figures/{_view.name}", _figure_route(_view), methods=["GET"],
                         tags=["figures"], summary=f"Plotly figure: {_view.summary}",
                         name=f"figure_{_view.name}")


class CompareBody(BaseModel):
    """Several models in one figure: each entry of ``models`` is a model as the GET
    endpoints take it (``{"ndf": "beckmann", "alpha": 0.2}``); ``view`` holds the
    parameters they share (``theta_i_deg``, ``n``, ``log``...)."""
    model_config = ConfigDict(extra="forbid")
    models: list[dict[str, Any]] = Field(min_length=1, description="model specs, one curve each")
    labels: Optional[list[str]] = Field(None, description="legend labels, one per model")
    view: dict[str, Any] = Field(default_factory=dict, description="shared view parameters")


def _difference_labels(specs: list[dict]) -> list[str]:
    """Legend labels naming what differs between the models (all of the title if nothing
    does): "ndf=ggx, alpha=0.2" / "ndf=beckmann, alpha=0.2" → "ggx" / "beckmann"."""
    keys = [k for k in dict.fromkeys(k for s in specs for k in s)
            if len({repr(s.get(k)) for s in specs}) > 1]
    if not keys:
        return [model_title(s) for s in specs]

    def show(k, value):
        return str(value) if k in OPTIONS else f"{k}={value:g}" if isinstance(value, float) else f"{k}={value}"
    return [", ".join(show(k, s.get(k)) for k in keys if s.get(k) is not None) or "default" for s in specs]


def _compare_route(view: View):
    def route(request: Request, body: CompareBody) -> Response:
        settings = request.app.state.settings
        limit = settings.max_compare_models
        if len(body.models) > limit:
            raise ParameterError("models", f"{len(body.models)} models; the limit is {limit} "
                             "(setting BRDF_MAX_COMPARE_MODELS)", status=413, loc="body")
        if body.labels is not None and len(body.labels) != len(body.models):
            raise ParameterError("labels", "give one label per model", loc="body")
        model_fields = set(schemas.ModelQuery.model_fields)
        if set(body.view) & model_fields:
            name = sorted(set(body.view) & model_fields)[0]
            raise ParameterError("view", f"{name} is a model parameter: put it in each model", loc="body")
        figures_, specs = [], []
        for k, model in enumerate(body.models):
            try:
                q = view.figure_query.model_validate({**body.view, **model})
            except ValidationError as exc:
                e = exc.errors()[0]
                field = ".".join(str(x) for x in e.get("loc", ()))
                raise ParameterError(f"models[{k}].{field}", f"models[{k}].{field}: {e.get('msg', '')}",
                                 loc="body") from None
            view.check(q, settings)
            try:
                spec = make_spec(**schemas.model_values(q))
            except ParameterError as exc:
                raise ParameterError(f"models[{k}].{exc.param}", f"models[{k}]: {exc.message}",
                                 loc="body") from None
            figures_.append(view.figure(view.compute(spec, q), spec, q))
            specs.append(spec.values)
        labels = body.labels or _difference_labels(specs)
        figure = overlay(figures_, labels, f"{view.summary}: {len(labels)} models", param="models")
        return Response(figures.to_json(figure), media_type="application/json")
    return route


for _view in VIEWS.values():
    router.add_api_route(
        f"/figures/{_view.name}", _compare_route(_view), methods=["POST"], tags=["figures"],
        summary=f"Compare models in one figure: {_view.summary}", name=f"compare_{_view.name}",
        openapi_extra={"requestBody": {"content": {"application/json": {"example": {
            "models": [{"ndf": "ggx", "alpha": 0.2}, {"ndf": "beckmann", "alpha": 0.2}],
            "view": {}}}}}})
