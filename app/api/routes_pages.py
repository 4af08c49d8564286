"""What the page builds itself from, and the pages that are not the explorer:
``GET /api/v1/views`` (every view: title, summary, fields with their role, endpoints),
``GET /api/v1/gallery`` (the gallery's entries), ``GET /embed/{view}`` (the figure alone,
for an iframe) and ``GET /gallery``."""
from pathlib import Path

from fastapi import APIRouter, Request
from fastapi.responses import FileResponse
from starlette.concurrency import run_in_threadpool

from .. import gallery
from ..views import VIEWS, lookup, vary
from .encode import json_response

router = APIRouter()


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
                    "fields": fields,
                    "vary": list(curves),
                    "data": f"/api/v1/{view.name}", "figure": f"/api/v1/figures/{view.name}",
                    "exports": {ext: f"/api/v1/figures/{view.name}.{ext}"
                                for ext in ("svg", "png", "csv", "json")},
                    "embed": f"/embed/{view.name}"})
    return out


@router.get("/api/v1/views", tags=["meta"], summary="Every view: its own parameters and endpoints",
            responses={200: {"content": {"application/json": {"example": [{
                "name": "lobe", "title": "BRDF lobe", "summary": "f in the plane of incidence",
                "fields": [{"name": "theta_i_deg", "type": "number", "default": 45.0,
                            "minimum": 0, "maximum": 90, "description": "polar angle",
                            "role": "geometry"}],
                "exports": {"svg": "/api/v1/figures/lobe.svg"}, "embed": "/embed/lobe"}]}}}})
def views():
    return json_response(views_payload())


@router.get("/api/v1/gallery", tags=["meta"], summary="The gallery's figures, with captions and links",
            responses={200: {"content": {"application/json": {"example": [{
                "id": "ndf-tails", "title": "NDF tails at matched α", "kind": "ndf",
                "caption": "…", "state": {"alpha": 0.3, "vary": "ndf", "values": "ggx,beckmann"},
                "explorer": "/?alpha=0.3&vary=ndf&values=ggx%2Cbeckmann&show=ndf",
                "svg": "/api/v1/figures/ndf.svg?alpha=0.3&vary=ndf&values=ggx%2Cbeckmann"}]}}}})
async def gallery_entries():
    return json_response(await run_in_threadpool(gallery.available))


def _static(request: Request, name: str) -> Path:
    """A file of the app's static directory (wherever create_app mounted it)."""
    for route in request.app.router.routes:
        if getattr(route, "name", None) == "static":
            return Path(route.app.directory) / name
    return Path(__file__).resolve().parents[2] / "static" / name


_HTML = {200: {"content": {"text/html": {"example": "<!doctype html><html lang=\"en\">…</html>"}}}}


@router.get("/embed/{kind}", tags=["pages"], response_class=FileResponse, responses=_HTML,
            summary="The figure alone, sized to its iframe (controls=1 adds its sliders)",
            description="Example: `<iframe src=\"/embed/lobe?alpha=0.2&theta_i_deg=60\" "
                        "width=\"640\" height=\"420\"></iframe>`. Takes the figure's query "
                        "parameters; `controls=1` adds the sliders that matter for this "
                        "figure, `buttons=0` hides the export buttons.")
def embed(request: Request, kind: str):
    lookup(kind)                             # 404 naming the views there are
    return FileResponse(_static(request, "embed.html"), media_type="text/html")


@router.get("/gallery", tags=["pages"], response_class=FileResponse, responses=_HTML,
            summary="Canonical figures with captions, each a link into the explorer")
def gallery_page(request: Request):
    return FileResponse(_static(request, "gallery.html"), media_type="text/html")
