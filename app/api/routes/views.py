"""Each view's numbers, ``GET /api/v1/{view}`` (the arrays behind its figure, through the
views' pipeline), and ``GET /api/v1/views``: every view with its title, summary, fields
(with their role) and endpoints, what the page builds its panels from."""
from typing import Annotated

from fastapi import APIRouter, Query, Request, Response

from ... import work
from ...views import VIEWS, View, run, vary
from ..deps import Route, SettingsDep
from ..encode import json_response

router = APIRouter(prefix="/api/v1", route_class=Route)


def _field_info(name: str, schema: dict) -> dict:
    prop = dict(schema)
    if "anyOf" in prop:               # Optional[x]: the non-null branch
        branch = next((b for b in prop["anyOf"] if b.get("type") != "null"), {})
        prop = {**branch, **{k: v for k, v in prop.items() if k != "anyOf"}}
    out = {"name": name, "type": prop.get("type", "string"), "default": prop.get("default"),
           "description": prop.get("description", "")}
    for key in ("minimum", "maximum", "exclusiveMinimum", "exclusiveMaximum", "enum"):
        if key in prop:
            out[key] = prop[key]
    if "const" in prop:
        out["enum"] = [prop["const"]]
    if "x-applies-to" in prop:        # shown and sent only where it applies (schemas.applies_to)
        out["applies_to"] = prop["x-applies-to"]
    return out


def views_payload() -> list[dict]:
    out = []
    for view in VIEWS.values():
        props = view.figure_query.model_json_schema()["properties"]
        fields = [{**_field_info(n, props[n]), "role": view.role(n)} for n in view.fields()]
        curves = vary.vary_choices(view)
        out.append({"name": view.name, "title": view.title, "summary": view.summary,
                    **view.declared(), "fields": fields,
                    "vary": list(curves),
                    "data": f"/api/v1/{view.name}", "figure": f"/api/v1/figures/{view.name}",
                    "exports": {ext: f"/api/v1/figures/{view.name}.{ext}"
                                for ext in ("svg", "png", "csv", "json")},
                    "embed": f"/embed/{view.name}"})
    return out


@router.get("/views", tags=["meta"], summary="Every view: its own parameters and endpoints",
            responses={200: {"content": {"application/json": {"example": [{
                "name": "lobe", "title": "BRDF lobe", "summary": "f in the plane of incidence",
                "fields": [{"name": "theta_i_deg", "type": "number", "default": 45.0,
                            "minimum": 0, "maximum": 90, "description": "polar angle",
                            "role": "geometry"}],
                "exports": {"svg": "/api/v1/figures/lobe.svg"}, "embed": "/embed/lobe"}]}}}})
def views():
    return json_response(views_payload())


def _data_route(view: View):
    if work.is_heavy(view.name):    # computed in the heavy pool (app/work)
        async def heavy(settings: SettingsDep, q: Annotated[view.query, Query()]) -> Response:
            body, media = await work.view_answer(view.name, "data", q, settings)
            return Response(body, media_type=media)
        return heavy

    def route(settings: SettingsDep, q: Annotated[view.query, Query()]) -> Response:
        return json_response(run(view, q, settings).data)
    return route


for _view in VIEWS.values():
    router.add_api_route(f"/{_view.name}", _data_route(_view), methods=["GET"], tags=["data"],
                         summary=f"{_view.title}: {_view.summary}", name=f"data_{_view.name}")
