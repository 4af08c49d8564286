"""Data sets: upload (MERL .binary, CSV of samples or of one term), summary, delete, the
model's difference from the data, and each overlayable view with the data on its axes.
The work is in app/datasets; this module reads bodies and answers."""

import re
from typing import Annotated, Literal, Optional

from fastapi import APIRouter, Path, Query, Request, Response
from pydantic import Field, create_model
from starlette.concurrency import run_in_threadpool

from ... import figures, work
from ...config import Settings
from ...datasets import compare, formats, overlay
from ...figures import data_overlay as figure
from ...datasets.store import DatasetStore, content_id
from ...errors import ParameterError, TooLarge
from ...fit import run as fitting
from ...model import family_of, make_spec
from ...views import VIEWS, View, run, schemas
from ...work import costs, jobs
from ..deps import DatasetsDep, Route, SettingsDep
from ..encode import json_response

router = APIRouter(prefix="/api/v1", route_class=Route)

DataId = Annotated[str, Path(pattern=r"^[0-9a-f]{32}$", description="a data set's id (32 hex digits)",
                             examples=["3e071955855cb1a4a828bf3b009a1d2b"])]
_ANSWER = {"id": "1a2c1ba1124b3d9ca4d4913bf23ac299", "format": "samples_csv", "summary": {
    "format": "samples_csv", "bytes": 88, "kind": "brdf", "channels": ["f"], "count": 2,
    "fraction_measured": 1.0, "range": {"f": [0.25, 1.5]},
    "reciprocity": {"max_relative_error": None, "pairs": 0}, "albedo": {"mu": [], "E": {"f": []}}}}


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
                         "Data sets are kept in files shared by every worker, up to "
                         "BRDF_MAX_DATASETS_BYTES (a quarter of it per client), the least recently "
                         "used going first (a later request for it: 410 with the reason). The "
                         "answer's `token` is what DELETE needs.")
async def upload(request: Request, settings: SettingsDep, datasets: DatasetsDep,
                 format: Annotated[Optional[_FORMAT], Query(
                     description="insist on a format instead of detecting it")] = None) -> Response:
    content = await read_upload(request, settings.max_upload_bytes)
    seconds, fits = costs.upload_seconds(content)
    data, info = await work.run_heavy(jobs.upload, content, format, cost=seconds, fits=fits)
    data_id = content_id(data.format, content)
    client = request.client.host if request.client else ""
    token = await run_in_threadpool(datasets.put, data_id, data, info, client)
    return json_response({"id": data_id, "format": data.format, "summary": info, "token": token},
                         status_code=201)


@router.get("/datasets/{data_id}", tags=["datasets"], summary="A data set's summary",
            responses={200: {"content": {"application/json": {"example": _ANSWER}}}, 404: {"description": "No data set has this id"},
                       410: {"description": "The data set has expired (evicted or deleted)"}})
def dataset(datasets: DatasetsDep, data_id: DataId) -> Response:
    data, info = datasets.get(data_id, "data_id", "path")
    return json_response({"id": data_id, "format": data.format, "summary": info})


@router.delete("/datasets/{data_id}", tags=["datasets"], status_code=204, summary="Drop a data set",
               responses={403: {"description": "The token is missing or is not one its upload answered"},
                          404: {"description": "No data set has this id"},
                          410: {"description": "The data set has already expired"}})
def delete_dataset(datasets: DatasetsDep, data_id: DataId,
                   token: Annotated[Optional[str], Query(
                       max_length=64, description="the token the upload answered")] = None) -> Response:
    datasets.delete(data_id, token)
    return Response(status_code=204)


class DifferenceQuery(schemas.ModelQuery):
    channel: Optional[Literal["r", "g", "b", "luminance", "f", "D", "G1", "F"]] = Field(
        None, description="r, g, b or luminance (the default) of RGB data; D, G1 or F of term data")
    max_points: int = Field(5000, ge=1, le=50_000, description=(
        "points compared at most: a fixed-seed random subset of larger data sets"))


@router.get("/datasets/{data_id}/difference", tags=["datasets"],
            summary="Model − data at the data's points, and the largest relative error with where",
            description="relative_error = (data − model)/model where the model is positive and "
                        "the ratio is a float, null elsewhere; max_relative_error is the largest "
                        "in magnitude, `where` its angles, rms_relative_error their rms (all null "
                        "when no point has one).")
def difference(datasets: DatasetsDep, data_id: DataId, q: Annotated[DifferenceQuery, Query()]) -> Response:
    values = schemas.model_values(q)
    if "channel" not in family_of(values).own_names():   # the data's channel, not the model's
        values.pop("channel", None)
    spec = make_spec(**values)
    data, _ = datasets.get(data_id, "data_id", "path")
    result = compare.difference(data, spec.brdf(), q.channel, q.max_points)
    return json_response({"id": data_id, "model": fitting.as_model(spec.values), **result})


Channel = Optional[Literal["r", "g", "b", "luminance", "f", "D", "G1", "F"]]


def _overlay_query(view: View) -> type:
    """The view's figure query plus the data set's channel and the difference toggle."""
    return create_model(
        f"{view.name.title()}DataQuery", __base__=view.figure_query,
        channel=(Channel, Field(None, description="r, g, b or luminance (the default) of RGB data")),
        difference=(bool, Field(False, description="draw (data − model)/model instead")))


def _view_query(view: View, q):
    """The view's own query in the overlay's: the data's channel goes to the model only
    where the model has channels of its own (its family takes ``channel``)."""
    own = {k: getattr(q, k) for k in q.model_fields_set if k in view.figure_query.model_fields}
    if "channel" not in family_of(schemas.model_values(q)).own_names():
        own.pop("channel", None)
    return view.figure_query.model_validate(own)


def _overlay(datasets: DatasetStore, settings: Settings, view: View, data_id: str, q):
    """The view run for the model, the data on its axes, and the view's own query."""
    data, info = datasets.get(data_id, "data_id", "path")
    own = _view_query(view, q)
    result = run(view, own, settings)
    spec, arrays = result.spec, result.data
    extra = (info,) if view.name == "albedo" else ()
    found = overlay.OVERLAYS[view.name](data, spec.brdf(), arrays, q, q.channel, *extra)
    default = data.channels[0] if len(data.channels) == 1 or data.kind == "term" else "luminance"
    return spec, arrays, found, f"({q.channel or default})", own


def _overlay_data_route(view: View):
    model = _overlay_query(view)

    def route(datasets: DatasetsDep, settings: SettingsDep, data_id: DataId,
              q: Annotated[model, Query()]) -> Response:
        found = _overlay(datasets, settings, view, data_id, q)[2]
        return json_response(found)
    return route


def _overlay_figure_route(view: View):
    model = _overlay_query(view)

    def route(datasets: DatasetsDep, settings: SettingsDep, data_id: DataId,
              q: Annotated[model, Query()]) -> Response:
        spec, arrays, found, label, own = _overlay(datasets, settings, view, data_id, q)
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
