"""Exports of every view, the embed and gallery pages, and the views' own description.

For each view in VIEWS (the ones added later included), with the same query as its
figure route:

* ``GET /api/v1/figures/{kind}.svg`` and ``.png`` (+ ``width``, ``height``, ``scale``):
  rendered by kaleido in one headless Chromium per process (503 without Chromium);
* ``GET /api/v1/figures/{kind}.csv``: the numbers behind the figure, units in the header;
* ``GET /api/v1/figures/{kind}.json``: the figure JSON;

and all four take ``vary`` + ``values`` to overlay one curve per value.
``GET /embed/{kind}`` is the figure alone on a page (for an iframe), ``GET /gallery``
the gallery; ``GET /api/v1/views`` lists the views and their own parameters (the page
builds its panels from it), ``GET /api/v1/gallery`` the gallery's entries.
"""
# No "from __future__ import annotations": FastAPI must see the query models, which are
# local to the route factories, as objects.
import re
import time
from pathlib import Path
from typing import Annotated

from fastapi import APIRouter, Depends, Query, Request, Response
from fastapi.responses import FileResponse
from starlette.concurrency import run_in_threadpool

from .. import gallery
from ..export import build
from ..export.image import ImageRenderer, get_renderer
from .encode import json_response
from .views import VIEWS, View

router = APIRouter()
Renderer = Annotated[ImageRenderer, Depends(get_renderer)]

MEDIA = {"svg": "image/svg+xml", "png": "image/png", "csv": "text/csv; charset=utf-8",
         "json": "application/json"}

_SVG_EXAMPLE = ('<svg class="main-svg" xmlns="http://www.w3.org/2000/svg" width="800" '
                'height="560" viewBox="0 0 800 560">…</svg>')
_CSV_EXAMPLE = ("# view = ndf\n# phi_deg = 0\n# ndf = ggx\n# alpha = 0.3\ntheta_deg,D_per_sr\n"
                "0,3.5367765131532298\n0.5,3.5347584447016218\n…\n")
_PNG_NOTE = "PNG bytes: width·scale × height·scale pixels, RGBA."
_UNAVAILABLE = {"description": "No Chromium on the server: the message says what to install",
                "content": {"application/json": {"example": {"detail": [{
                    "loc": ["query", "image export"], "type": "busy",
                    "msg": "No Chromium found. Server-side image export needs a Chromium "
                           "browser: install it (Debian/Ubuntu: apt-get install chromium; …)"}]}}}}


def _filename(view: View, q, ext: str) -> str:
    """lobe-ggx-alpha0.3.svg: the kind and the model, safe for any file system."""
    parts = [view.name, getattr(q, "ndf", "") or ""]
    if getattr(q, "vary", None):
        parts.append(f"vary-{q.vary}")
    elif getattr(q, "alpha", None) is not None:
        parts.append(f"alpha{q.alpha:g}")
    name = "-".join(p for p in parts if p)
    return re.sub(r"[^A-Za-z0-9._-]", "_", name) + f".{ext}"


def _timing(**seconds: float) -> str:
    return ", ".join(f"{k};dur={v * 1000:.1f}" for k, v in seconds.items())


def _image_route(view: View, fmt: str):
    model = build.image_query(view)

    def route(request: Request, renderer: Renderer, q: Annotated[model, Query()]) -> Response:
        settings = request.app.state.settings
        build.check_image_size(q, settings)
        # a place in the export queue before any work: a full queue is a 503 at once
        with renderer.slot():
            t0 = time.perf_counter()
            produced = build.produce(view, q, settings)
            t1 = time.perf_counter()
            body = renderer.render(produced.figure, fmt, q.width, q.height, q.scale)
            t2 = time.perf_counter()
        return Response(body, media_type=MEDIA[fmt], headers={
            "Content-Disposition": f'inline; filename="{_filename(view, q, fmt)}"',
            "Server-Timing": _timing(compute=t1 - t0, render=t2 - t1)})
    return route


def _csv_route(view: View):
    model = build.export_query(view)

    def route(request: Request, q: Annotated[model, Query()]) -> Response:
        produced = build.produce(view, q, request.app.state.settings)
        return Response(produced.csv(), media_type=MEDIA["csv"], headers={
            "Content-Disposition": f'inline; filename="{_filename(view, q, "csv")}"'})
    return route


def _json_route(view: View):
    model = build.export_query(view)

    def route(request: Request, q: Annotated[model, Query()]) -> Response:
        produced = build.produce(view, q, request.app.state.settings)
        return Response(build.figure_json(produced), media_type=MEDIA["json"])
    return route


for _view in VIEWS.values():
    _example = f"/api/v1/figures/{_view.name}"
    router.add_api_route(
        f"/api/v1/figures/{_view.name}.svg", _image_route(_view, "svg"), methods=["GET"],
        tags=["exports"], name=f"export_svg_{_view.name}", response_class=Response,
        summary=f"SVG: {_view.summary}",
        description=f"Example: `{_example}.svg?alpha=0.2&width=1200&height=800`",
        responses={200: {"content": {"image/svg+xml": {"example": _SVG_EXAMPLE}}},
                   503: _UNAVAILABLE})
    router.add_api_route(
        f"/api/v1/figures/{_view.name}.png", _image_route(_view, "png"), methods=["GET"],
        tags=["exports"], name=f"export_png_{_view.name}", response_class=Response,
        summary=f"PNG: {_view.summary}",
        description=f"Example: `{_example}.png?alpha=0.2&width=1200&height=800&scale=2`. {_PNG_NOTE}",
        responses={200: {"content": {"image/png": {"schema": {"type": "string", "format": "binary"},
                                                   "example": "(binary PNG)"}}},
                   503: _UNAVAILABLE})
    router.add_api_route(
        f"/api/v1/figures/{_view.name}.csv", _csv_route(_view), methods=["GET"],
        tags=["exports"], name=f"export_csv_{_view.name}", response_class=Response,
        summary=f"CSV: {_view.summary}",
        description=f"Example: `{_example}.csv?alpha=0.2`. Header row with units; 2-D grids "
                    "in long format; `# name = value` lines above it give the state.",
        responses={200: {"content": {"text/csv": {"example": _CSV_EXAMPLE}}}})
    router.add_api_route(
        f"/api/v1/figures/{_view.name}.json", _json_route(_view), methods=["GET"],
        tags=["exports"], name=f"export_json_{_view.name}", response_class=Response,
        summary=f"Figure JSON, with vary/values overlays: {_view.summary}",
        description=f"Example: `{_example}.json?vary=alpha&values=0.1,0.3`",
        responses={200: {"content": {"application/json": {"example": {
            "data": [{"type": "scatter", "name": "alpha=0.1", "x": [0, 0.5], "y": [31.8, 31.6]}],
            "layout": {"title": {"text": "D(θ_m) — alpha = 0.1, 0.3"}}}}}}})


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
        fields = [_field_info(n, props[n]) for n in build.view_fields(view)]
        curves = build.vary_choices(view)
        out.append({"name": view.name, "summary": view.summary, "fields": fields,
                    "vary": list(curves),
                    "data": f"/api/v1/{view.name}", "figure": f"/api/v1/figures/{view.name}",
                    "exports": {ext: f"/api/v1/figures/{view.name}.{ext}"
                                for ext in ("svg", "png", "csv", "json")},
                    "embed": f"/embed/{view.name}"})
    return out


@router.get("/api/v1/views", tags=["meta"], summary="Every view: its own parameters and endpoints",
            responses={200: {"content": {"application/json": {"example": [{
                "name": "lobe", "summary": "f in the plane of incidence",
                "fields": [{"name": "theta_i_deg", "type": "number", "default": 45.0,
                            "minimum": 0, "maximum": 90, "description": "polar angle"}],
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
    build.lookup(kind)                       # 404 naming the kinds there are
    return FileResponse(_static(request, "embed.html"), media_type="text/html")


@router.get("/gallery", tags=["pages"], response_class=FileResponse, responses=_HTML,
            summary="Canonical figures with captions, each a link into the explorer")
def gallery_page(request: Request):
    return FileResponse(_static(request, "gallery.html"), media_type="text/html")
