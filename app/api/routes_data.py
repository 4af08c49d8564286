"""Data sets (upload, summary, delete), fits of models to them, and models exported as
data. The work is in app/datasets and app/fit; this file reads bodies and answers."""

import re
import threading
from typing import Annotated, Any, Literal, Optional

import numpy as np
from fastapi import APIRouter, Body, Path, Query, Request, Response
from pydantic import BaseModel, ConfigDict, Field, create_model
from starlette.concurrency import run_in_threadpool

from .. import figures
from ..datasets import compare, figure, formats, overlay, summary, tabulate
from ..fit import run as fitting
from ..fit.problem import MEASURES
from ..integrate import budget
from ..datasets.store import DatasetStore, content_id
from ..errors import ParameterError, TooLarge
from ..model import make_spec
from ..views import schemas
from .encode import json_response
from ..views import VIEWS, View, run
from .http.query_route import QueryModelRoute

router = APIRouter(prefix="/api/v1", route_class=QueryModelRoute)

_STORE_LOCK = threading.Lock()
DataId = Annotated[str, Path(pattern=r"^[0-9a-f]{32}$", description="a data set's id (32 hex digits)",
                             examples=["3e071955855cb1a4a828bf3b009a1d2b"])]
_ANSWER = {"id": "1a2c1ba1124b3d9ca4d4913bf23ac299", "format": "samples_csv", "summary": {
    "format": "samples_csv", "bytes": 88, "kind": "brdf", "channels": ["f"], "count": 2,
    "fraction_measured": 1.0, "range": {"f": [0.25, 1.5]},
    "reciprocity": {"max_relative_error": None, "pairs": 0}, "albedo": {"mu": [], "E": {"f": []}}}}


def store(request: Request) -> DatasetStore:
    """The app's data-set store, made on first use."""
    with _STORE_LOCK:
        if not hasattr(request.app.state, "datasets"):
            request.app.state.datasets = DatasetStore(
                request.app.state.settings.max_datasets_bytes)
        return request.app.state.datasets


async def read_upload(request: Request, limit: int) -> bytes:
    """The body, refused (413) as soon as it is known to exceed ``limit`` bytes: from its
    Content-Length before anything is read, else while it streams."""
    encoding = request.headers.get("content-encoding", "identity").strip().lower()
    if encoding not in ("", "identity"):
        raise ParameterError("content-encoding", f"Content-Encoding {encoding!r} is not accepted: "
                                                 "send the file uncompressed", status=415, loc="header")
    message = f"an upload may have {limit} bytes (setting BRDF_MAX_UPLOAD_BYTES)"
    length = request.headers.get("content-length", "")
    if length.isdigit() and int(length) > limit:
        raise TooLarge("file", f"the upload has {int(length)} bytes; {message}", loc="body")
    chunks, received = [], 0
    async for chunk in request.stream():
        received += len(chunk)
        if received > limit:
            raise TooLarge("file", f"the upload has more than {limit} bytes; {message}", loc="body")
        chunks.append(chunk)
    body = b"".join(chunks)
    kind = request.headers.get("content-type", "")
    return multipart_file(body, kind) if kind.lower().startswith("multipart/form-data") else body


def multipart_file(body: bytes, content_type: str) -> bytes:
    """The part named ``file`` of a multipart/form-data body (RFC 7578), byte-exact."""
    found = re.search(r'boundary="?([^";]+)"?', content_type)
    if not found:
        raise ParameterError("content-type", "multipart/form-data needs a boundary parameter",
                             loc="header")
    delimiter = b"--" + found.group(1).encode("latin-1")
    for part in body.split(delimiter)[1:]:
        if part.startswith(b"--"):
            break
        head, sep, content = part.partition(b"\r\n\r\n")
        if sep and re.search(rb'name="file"', head):
            return content[:-2] if content.endswith(b"\r\n") else content
    raise ParameterError("file", "the multipart body has no part named \"file\"", loc="body")


_UPLOAD_BODY = {"x-body-limit": "max_upload_bytes", "requestBody": {"required": True, "content": {
    "multipart/form-data": {"schema": {"type": "object", "required": ["file"], "properties": {
        "file": {"type": "string", "format": "binary"}}}},
    "application/octet-stream": {"schema": {"type": "string", "format": "binary"}},
    "text/csv": {"schema": {"type": "string"}, "example": (
        "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n30,0,30,180,1.5\n45,0,20,90,0.25\n")}}}}
_FORMAT = Literal[tuple(formats.FORMATS)]


@router.post("/datasets", tags=["datasets"], status_code=201, openapi_extra=_UPLOAD_BODY,
             summary="Upload a data set: MERL .binary, or CSV of BRDF samples or of one term",
             description="The body is the file (any Content-Type), or multipart/form-data with "
                         "the file in the field `file`. The format is found from the content; "
                         "`format` insists on one: " + "; ".join(
                             f"`{k}`: {v}" for k, v in formats.FORMATS.items()) +
                         ". The id is a hash of the content: the same file gets the same id. "
                         "Data sets are kept in memory up to BRDF_MAX_DATASETS_BYTES, the least "
                         "recently used going first.")
async def upload(request: Request, format: Annotated[Optional[_FORMAT], Query(
        description="insist on a format instead of detecting it")] = None) -> Response:
    content = await read_upload(request, request.app.state.settings.max_upload_bytes)
    data = await run_in_threadpool(formats.load, content, format)
    data_id = content_id(data.format, content)
    datasets = store(request)
    if data_id not in datasets:
        datasets.put(data_id, data, await run_in_threadpool(summary.summarize, data))
    _, info = datasets.get(data_id)
    return json_response({"id": data_id, "format": data.format, "summary": info}, status_code=201)


@router.get("/datasets/{data_id}", tags=["datasets"], summary="A data set's summary",
            responses={200: {"content": {"application/json": {"example": _ANSWER}}}, 404: {"description": "No data set has this id"},
                       410: {"description": "The data set has expired (evicted or deleted)"}})
def dataset(request: Request, data_id: DataId) -> Response:
    data, info = store(request).get(data_id, "data_id", "path")
    return json_response({"id": data_id, "format": data.format, "summary": info})


@router.delete("/datasets/{data_id}", tags=["datasets"], status_code=204, summary="Drop a data set",
               responses={404: {"description": "No data set has this id"},
                          410: {"description": "The data set has already expired"}})
def delete_dataset(request: Request, data_id: DataId) -> Response:
    store(request).delete(data_id)
    return Response(status_code=204)


class DifferenceQuery(schemas.ModelQuery):
    channel: Optional[Literal["r", "g", "b", "luminance", "f", "D", "G1", "F"]] = Field(
        None, description="r, g, b or luminance (the default) of RGB data; D, G1 or F of term data")
    max_points: int = Field(5000, ge=1, le=50_000, description=(
        "points compared at most: a fixed-seed random subset of larger data sets"))


@router.get("/datasets/{data_id}/difference", tags=["datasets"],
            summary="Model − data at the data's points, and the largest relative error with where",
            description="relative_error = (data − model)/model where the model is positive; "
                        "max_relative_error is the largest in magnitude, `where` its angles.")
def difference(request: Request, data_id: DataId, q: Annotated[DifferenceQuery, Query()]) -> Response:
    values = schemas.model_values(q)
    if values.get("model") != "principled":      # the data's channel, not the model's
        values.pop("channel", None)
    spec = make_spec(**values)
    data, _ = store(request).get(data_id, "data_id", "path")
    result = compare.difference(data, spec.brdf(), q.channel, q.max_points)
    return json_response({"id": data_id, "model": fitting.as_model(spec.values), **result})


class SamplesExportQuery(schemas.ModelQuery):
    n_theta: int = Field(19, ge=2, le=91, description="polar angles θ_i = θ_o, 0..90° (both ends)")
    n_phi: int = Field(24, ge=1, le=360, description="azimuths φ_o = k·360°/n_phi; φ_i = 0")


@router.get("/export/model.binary", tags=["exports"], response_class=Response,
            summary="The model as a MERL .binary file (the same in R, G and B)",
            description="f at the centre of each of the 90 × 90 × 180 cells; cells with a "
                        "direction below the horizon are marked not measured. ~35 MB.",
            responses={200: {"content": {"application/octet-stream": {
                "schema": {"type": "string", "format": "binary"}}}},
                       413: {"description": "The table of this model takes longer than the "
                                            "request's whole time budget (BRDF_MAX_SECONDS)"},
                       503: {"description": "The table would take longer than what is left of "
                                            "the request's time budget; Retry-After says about "
                                            "how long it takes"}})
def export_merl(q: Annotated[schemas.ModelQuery, Query()]) -> Response:
    spec = make_spec(**schemas.model_values(q))
    content = tabulate.merl_bytes(spec.brdf())
    return Response(content, media_type="application/octet-stream",
                    headers={"content-disposition": 'attachment; filename="model.binary"'})


@router.get("/export/model.csv", tags=["exports"], response_class=Response,
            summary="The model as a CSV of BRDF samples (the format POST /datasets reads)",
            responses={200: {"content": {"text/csv": {"example": ",".join(tabulate.SAMPLE_COLUMNS)}}}})
def export_samples(q: Annotated[SamplesExportQuery, Query()]) -> Response:
    spec = make_spec(**schemas.model_values(q))
    text = tabulate.samples_csv(spec.brdf(), np.linspace(0.0, 90.0, q.n_theta),
                                np.arange(q.n_phi) * 360.0 / q.n_phi)
    return Response(text, media_type="text/csv",
                    headers={"content-disposition": 'attachment; filename="model.csv"'})


class FitBody(BaseModel):
    """A fit: which data, which model family with which parameters fixed, which free."""
    model_config = ConfigDict(extra="forbid", allow_inf_nan=False)
    data: str = Field(pattern=r"^[0-9a-f]{32}$", description="the data set's id")
    model: dict[str, Any] = Field(default_factory=dict, description=(
        "the model family and its fixed parameters, as every endpoint takes them; the free "
        "ones start from the values given here (or their defaults)"))
    free: list[str] = Field(min_length=1, max_length=12, description="parameters to fit")
    measure: Literal[MEASURES] = Field("log", description="; ".join(
        f"{k}: {v}" for k, v in fitting.FAVOURS.items()))
    channel: Optional[Literal["r", "g", "b", "luminance", "f", "D", "G1", "F"]] = Field(
        None, description="r, g, b or luminance (the default) of RGB data; D, G1 or F of term data")
    fit_all: bool = Field(False, description="fit every NDF with the rest of the model and rank "
                                             "them by residual")
    seconds: float = Field(5.0, gt=0.0, le=60.0, description=(
        "time budget of one model's fit (fit_all: of all of them together), within the "
        "request's own (BRDF_MAX_SECONDS); a fit stopped by it answers the best point reached"))
    max_points: int = Field(fitting.MAX_POINTS, ge=10, le=200_000, description=(
        "measured points used at most: a fixed-seed random subset of larger data sets"))


#: of the request's time budget, the part a fit may take: the rest encodes the answer
FIT_SHARE = 0.8


@router.post("/fit", tags=["datasets"], summary="Fit a model to a data set (least squares)",
             description="Answers the fitted parameters with standard errors from the Jacobian "
                         "at the optimum, the residual, evaluations and seconds, and `model`: the "
                         "whole fitted model, to send to any endpoint as it is.",
             responses={404: {"description": "No data set has the id in `data`"},
                        410: {"description": "The data set in `data` has expired (evicted or deleted)"}})
def fit(request: Request, body: Annotated[FitBody, Body(openapi_examples={"GGX to a MERL file": {
        "summary": "α, F0 and kd of GGX, red channel, log measure",
        "value": {"data": "3e071955855cb1a4a828bf3b009a1d2b", "model": {"ndf": "ggx", "alpha": 0.3},
                  "free": ["alpha", "f0", "kd"], "measure": "log", "channel": "r"}}})]) -> Response:
    seconds = body.seconds
    request_budget = budget.current()
    if request_budget is not None:
        seconds = min(seconds, FIT_SHARE * (request_budget.seconds - request_budget.elapsed()))
    data, _ = store(request).get(body.data)
    run = fitting.fit_all if body.fit_all else fitting.fit
    result = run(data, body.model, body.free, body.measure, body.channel, seconds, body.max_points)
    return json_response({"data": body.data, **result})


Channel = Optional[Literal["r", "g", "b", "luminance", "f", "D", "G1", "F"]]


def _overlay_query(view: View) -> type:
    """The view's figure query plus the data set's channel and the difference toggle."""
    return create_model(
        f"{view.name.title()}DataQuery", __base__=view.figure_query,
        channel=(Channel, Field(None, description="r, g, b or luminance (the default) of RGB data")),
        difference=(bool, Field(False, description="draw (data − model)/model instead")))


def _view_query(view: View, q):
    """The view's own query in the overlay's: the data's channel goes to the model only
    where the model has channels of its own (model=principled)."""
    own = {k: getattr(q, k) for k in q.model_fields_set if k in view.figure_query.model_fields}
    if getattr(q, "model", None) != "principled":
        own.pop("channel", None)
    return view.figure_query.model_validate(own)


def _overlay(request: Request, view: View, data_id: str, q):
    """The view run for the model, the data on its axes, and the view's own query."""
    data, info = store(request).get(data_id, "data_id", "path")
    own = _view_query(view, q)
    result = run(view, own, request.app.state.settings)
    spec, arrays = result.spec, result.data
    extra = (info,) if view.name == "albedo" else ()
    found = overlay.OVERLAYS[view.name](data, spec.brdf(), arrays, q, q.channel, *extra)
    default = data.channels[0] if len(data.channels) == 1 or data.kind == "term" else "luminance"
    return spec, arrays, found, f"({q.channel or default})", own


def _overlay_data_route(view: View):
    model = _overlay_query(view)

    def route(request: Request, data_id: DataId, q: Annotated[model, Query()]) -> Response:
        found = _overlay(request, view, data_id, q)[2]
        return json_response(found)
    return route


def _overlay_figure_route(view: View):
    model = _overlay_query(view)

    def route(request: Request, data_id: DataId, q: Annotated[model, Query()]) -> Response:
        spec, arrays, found, label, own = _overlay(request, view, data_id, q)
        if q.difference:
            return Response(figures.to_json(figure.relative_error(found, label)),
                            media_type="application/json")
        model_figure = view.figure(arrays, spec, own)
        data_figure = None
        if model_figure["data"][0].get("type") not in figure.CURVES:
            data_figure = view.figure({**arrays, **found["axes"], found["key"]: found["data"]}, spec, own)
        return Response(figures.to_json(figure.with_data(model_figure, found, label, data_figure)),
                        media_type="application/json")
    return route


for _name in overlay.OVERLAYS:
    _view = VIEWS[_name]
    router.add_api_route(
        f"/datasets/{{data_id}}/{_name}", _overlay_data_route(_view), methods=["GET"],
        tags=["datasets"], name=f"data_overlay_{_name}",
        summary=f"{_view.title} — with the data set on the same axes: data, model, model − data, "
                "the largest relative error and where")
    router.add_api_route(
        f"/datasets/{{data_id}}/figures/{_name}", _overlay_figure_route(_view), methods=["GET"],
        tags=["datasets"], name=f"figure_overlay_{_name}",
        summary=f"Plotly figure: {_view.title} — with the data set (difference=true: "
                "(data − model)/model)")
