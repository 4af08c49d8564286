"""Figures and their exports, for every view:

* ``GET /api/v1/figures/{view}`` (and the same at ``.json``): the Plotly figure; with
  ``vary`` + ``values`` one curve per value;
* ``POST /api/v1/figures/{view}``: several models in one figure (``models[]``);
* ``GET /api/v1/figures/{view}.svg`` / ``.png`` (+ ``width``, ``height``, ``scale``):
  rendered by kaleido in one headless Chromium per process (503 without Chromium);
* ``GET /api/v1/figures/{view}.csv``: the numbers behind the figure, units in the header.

Every one of them takes the same query and goes through :mod:`app.views`' pipeline
(via :mod:`app.export.build`). An unknown view or format is a 404 listing those there are.
"""
# No "from __future__ import annotations": FastAPI must see the query models, which are
# local to the route factories, as objects.
import re
import time
from typing import Annotated, Any, Optional

from fastapi import APIRouter, HTTPException, Query, Request, Response
from pydantic import BaseModel, ConfigDict, Field, ValidationError
from starlette.concurrency import run_in_threadpool

from ... import figures, work
from ...errors import ParameterError
from ...export import build
from ...figures.titles import file_stem
from ...views import VIEWS, View, compare, lookup, schemas
from ..deps import RendererDep, Route, SettingsDep

router = APIRouter(prefix="/api/v1/figures", route_class=Route)

FORMATS = ("svg", "png", "csv", "json")
#: the formats drawn by the image renderer
IMAGES = ("svg", "png")
#: a format twin (``/figures/lobe.svg``): out of the document, which shows all of them as
#: one operation (:func:`format_operation`), and in the request guard's index
TWIN = {"x-format-twin": True}
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
    """The view and every parameter that differs from the defaults (the model's and the
    view's own), as the figure's title names them: two slides never share a file name."""
    values = schemas.spec_of(q).values      # valid: the route computed it already
    if getattr(q, "vary", None):
        return f"{file_stem(view.name, values)}-vary-{re.sub(r'[^A-Za-z0-9._-]', '_', q.vary)}.{ext}"
    own = {name: getattr(q, name) for name in view.fields()
           if name not in build.EXPORT_FIELDS and name in q.model_fields_set}
    defaults = {name: f.default for name, f in type(q).model_fields.items()}
    return f"{file_stem(view.name, values, own, defaults)}.{ext}"


def _timing(**seconds: float) -> str:
    return ", ".join(f"{k};dur={v * 1000:.1f}" for k, v in seconds.items())


def image_body(view: View, fmt: str, q, settings, renderer) -> Response:
    """The answer of ``GET /api/v1/figures/{view}.svg`` or ``.png`` (POST /api/v1/batch
    answers such entries with it too)."""
    build.check_image_size(q, settings)
    # a place in the export queue before any work: a full queue is a 503 at once
    with renderer.slot():
        t0 = time.perf_counter()
        produced = build.produce(view, q, settings)
        return rendered(view, fmt, q, produced.figure, renderer, time.perf_counter() - t0)


def rendered(view: View, fmt: str, q, figure: dict, renderer, compute_seconds: float) -> Response:
    """The image answer of ``figure`` (computed here, or in the heavy pool), rendered
    within what is left of the request's time budget."""
    t0 = time.perf_counter()
    body = renderer.render(figure, fmt, q.width, q.height, q.scale)
    return Response(body, media_type=MEDIA[fmt], headers={
        "Content-Disposition": f'inline; filename="{_filename(view, q, fmt)}"',
        "Server-Timing": _timing(compute=compute_seconds, render=time.perf_counter() - t0)})


def csv_body(view: View, q, settings) -> Response:
    """The answer of ``GET /api/v1/figures/{view}.csv`` (and of such a batch entry)."""
    produced = build.produce(view, q, settings)
    return Response(produced.csv(), media_type=MEDIA["csv"], headers={
        "Content-Disposition": f'inline; filename="{_filename(view, q, "csv")}"'})


def _image_route(view: View, fmt: str):
    model = build.image_query(view)
    if work.is_heavy(view.name):    # the figure computed in the heavy pool, drawn here
        async def heavy(settings: SettingsDep, renderer: RendererDep,
                        q: Annotated[model, Query()]) -> Response:
            build.check_image_size(q, settings)
            t0 = time.perf_counter()
            figure = await work.view_answer(view.name, fmt, q, settings)
            return await run_in_threadpool(rendered, view, fmt, q, figure, renderer,
                                           time.perf_counter() - t0)
        return heavy

    def route(settings: SettingsDep, renderer: RendererDep, q: Annotated[model, Query()]) -> Response:
        return image_body(view, fmt, q, settings, renderer)
    return route


def _csv_route(view: View):
    model = build.export_query(view)
    if work.is_heavy(view.name):
        async def heavy(settings: SettingsDep, q: Annotated[model, Query()]) -> Response:
            body, media = await work.view_answer(view.name, "csv", q, settings)
            return Response(body, media_type=media, headers={
                "Content-Disposition": f'inline; filename="{_filename(view, q, "csv")}"'})
        return heavy

    def route(settings: SettingsDep, q: Annotated[model, Query()]) -> Response:
        return csv_body(view, q, settings)
    return route


def figure_body(view: View, q, settings) -> bytes:
    """The answer of ``GET /api/v1/figures/{view}``: the view's pipeline, as Plotly JSON
    (POST /api/v1/batch answers its entries with it too)."""
    return build.figure_json(build.produce(view, q, settings)).encode()


def _figure_route(view: View):
    model = build.export_query(view)
    if work.is_heavy(view.name):    # computed in the heavy pool (app/work), as JSON
        async def heavy(settings: SettingsDep, q: Annotated[model, Query()]) -> Response:
            body, media = await work.view_answer(view.name, "json", q, settings)
            return Response(body, media_type=media)
        return heavy

    def route(settings: SettingsDep, q: Annotated[model, Query()]) -> Response:
        return Response(figure_body(view, q, settings), media_type=MEDIA["json"])
    return route


class CompareBody(BaseModel):
    """Several models in one figure: each entry of ``models`` is a model as the GET
    endpoints take it (``{"ndf": "beckmann", "alpha": 0.2}``); ``view`` holds the
    parameters they share (``theta_i_deg``, ``n``, ``log``...)."""
    model_config = ConfigDict(extra="forbid")
    models: list[dict[str, Any]] = Field(min_length=1, description="model specs, one curve each")
    labels: Optional[list[str]] = Field(None, description="legend labels, one per model")
    view: dict[str, Any] = Field(default_factory=dict, description="shared view parameters")


def _compare_route(view: View):
    def route(settings: SettingsDep, body: CompareBody) -> Response:
        limit = settings.max_compare_models
        if len(body.models) > limit:
            raise ParameterError("models", f"{len(body.models)} models; the limit is {limit} "
                                 "(setting BRDF_MAX_COMPARE_MODELS)", status=413, loc="body")
        if body.labels is not None and len(body.labels) != len(body.models):
            raise ParameterError("labels", "give one label per model", loc="body")
        shared = sorted(set(body.view) & set(schemas.ModelQuery.model_fields))
        if shared:
            raise ParameterError("view", f"{shared[0]} is a model parameter: put it in each model",
                                 loc="body")
        queries = []
        for k, model in enumerate(body.models):
            try:
                queries.append(view.figure_query.model_validate({**body.view, **model}))
            except ValidationError as exc:
                e = exc.errors()[0]
                name = ".".join(str(x) for x in e.get("loc", ()))
                raise ParameterError(f"models[{k}].{name}", f"models[{k}].{name}: {e.get('msg', '')}",
                                     loc="body") from None
        comparison = compare(view, queries, body.labels, None, settings,
                             param="models", where=[f"models[{k}]" for k in range(len(queries))])
        return Response(figures.to_json(comparison.figure), media_type=MEDIA["json"])
    return route


# the figures first, their exports after: FastAPI tries routes in order (~10 µs each)
for _view in VIEWS.values():
    _example = f"/api/v1/figures/{_view.name}"
    _figure = _figure_route(_view)
    for _path, _name in ((f"/{_view.name}", f"figure_{_view.name}"),
                         (f"/{_view.name}.json", f"export_json_{_view.name}")):
        router.add_api_route(
            _path, _figure, methods=["GET"], tags=["figures"], name=_name, response_class=Response,
            include_in_schema=_path == f"/{_view.name}", openapi_extra=TWIN if "." in _path else None,
            summary=f"Plotly figure: {_view.title}",
            description=f"{_view.summary} `vary` + `values` draw one curve per value. Example: "
                        f"`{_example}?vary=alpha&values=0.1,0.3`",
            responses={200: {"content": {"application/json": {"example": {
                "data": [{"type": "scatter", "name": "alpha=0.1", "x": [0, 0.5], "y": [31.8, 31.6]}],
                "layout": {"title": {"text": "D(θ_m) — alpha = 0.1, 0.3"}}}}}}})
    router.add_api_route(
        f"/{_view.name}", _compare_route(_view), methods=["POST"], tags=["figures"],
        summary=f"Compare models in one figure: {_view.title}", name=f"compare_{_view.name}",
        openapi_extra={"requestBody": {"content": {"application/json": {"example": {
            "models": [{"ndf": "ggx", "alpha": 0.2}, {"ndf": "beckmann", "alpha": 0.2}],
            "view": {}}}}}})


for _view in VIEWS.values():
    _example = f"/api/v1/figures/{_view.name}"
    router.add_api_route(
        f"/{_view.name}.svg", include_in_schema=False, openapi_extra=TWIN,
        endpoint=_image_route(_view, "svg"), methods=["GET"],
        tags=["exports"], name=f"export_svg_{_view.name}", response_class=Response,
        summary=f"SVG: {_view.title}",
        description=f"Example: `{_example}.svg?alpha=0.2&width=1200&height=800`",
        responses={200: {"content": {"image/svg+xml": {"example": _SVG_EXAMPLE}}},
                   503: _UNAVAILABLE})
    router.add_api_route(
        f"/{_view.name}.png", include_in_schema=False, openapi_extra=TWIN,
        endpoint=_image_route(_view, "png"), methods=["GET"],
        tags=["exports"], name=f"export_png_{_view.name}", response_class=Response,
        summary=f"PNG: {_view.title}",
        description=f"Example: `{_example}.png?alpha=0.2&width=1200&height=800&scale=2`. {_PNG_NOTE}",
        responses={200: {"content": {"image/png": {"schema": {"type": "string", "format": "binary"},
                                                   "example": "(binary PNG)"}}},
                   503: _UNAVAILABLE})
    router.add_api_route(
        f"/{_view.name}.csv", include_in_schema=False, openapi_extra=TWIN,
        endpoint=_csv_route(_view), methods=["GET"],
        tags=["exports"], name=f"export_csv_{_view.name}", response_class=Response,
        summary=f"CSV: {_view.title}",
        description=f"Example: `{_example}.csv?alpha=0.2`. Header row with units; 2-D grids "
                    "in long format; `# name = value` lines above it give the state.",
        responses={200: {"content": {"text/csv": {"example": _CSV_EXAMPLE}}}})



@router.api_route("/{name}", methods=["GET", "POST"], include_in_schema=False)
def unknown_figure(name: str):
    """Any other figure path: a 404 that lists the views and formats there are."""
    view, dot, fmt = name.partition(".")
    lookup(view)
    if fmt in FORMATS or not dot:         # a known figure, another method
        raise HTTPException(405, "Method Not Allowed")
    raise ParameterError("format", f"unknown format {fmt!r} for figures/{view}; the formats are "
                                   f"{', '.join(FORMATS)}", status=404, loc="path")




def format_operation() -> dict:
    """The one documented operation of every view's format twins:
    ``GET /api/v1/figures/{view}.{format}``."""
    image = build.image_query(next(iter(VIEWS.values()))).model_fields
    size = [{"name": n, "in": "query", "required": False,
             "description": f"{image[n].description} (svg, png)",
             "schema": {"type": "integer" if n != "scale" else "number", "default": image[n].default}}
            for n in ("width", "height", "scale")]
    return {"get": {
        "tags": ["figures"], "operationId": "figure_export", "summary": "A figure as SVG, PNG, CSV or JSON",
        "description": "Every view in every format: the query is the view's own, as `GET "
                       "/api/v1/figures/{view}` lists it (and `vary` + `values`); `width`, "
                       "`height` and `scale` size an image. Example: `/api/v1/figures/lobe.svg?"
                       "alpha=0.2&width=1200&height=800`. SVG and PNG are rendered by a headless "
                       "Chromium on the server (503 without one); CSV has a header row with units.",
        "parameters": [
            {"name": "view", "in": "path", "required": True, "schema": {"type": "string", "enum": list(VIEWS)},
             "example": "lobe"},
            {"name": "format", "in": "path", "required": True,
             "schema": {"type": "string", "enum": list(FORMATS)}, "example": "svg"}, *size],
        "responses": {"200": {"description": "The figure in the format asked for", "content": {
            MEDIA[f].split(";")[0]: {"example": {"svg": _SVG_EXAMPLE, "csv": _CSV_EXAMPLE,
                                                  "png": "(binary PNG)", "json": {"data": [], "layout": {}}}[f]}
            for f in FORMATS}}, "503": _UNAVAILABLE}}}
