"""POST /api/v1/batch: several figure GETs in one round trip (the page's panels, one
request per slider move instead of one per panel).

Each entry of ``requests`` is the path and query of a ``GET /api/v1/figures/...``; its
answer is that GET's status, Cache-Control and JSON body (null for a body that is not
JSON: a CSV, an image), in order, and a 503's Retry-After as ``retry_after``. Every entry
is judged as its GET would be (the request guard's query checks, the route's query
model), then computed by the function its GET route calls, one after another in one
worker thread, all under the request's one time budget (BRDF_MAX_SECONDS): an entry
reached once that budget is spent, or whose predicted cost no longer fits what is left,
is answered 503 with its retry_after, and the rest are computed (issue 36).
"""
from __future__ import annotations

import json
import math
from urllib.parse import urlsplit

from fastapi import APIRouter, Request, Response
from fastapi.exceptions import RequestValidationError
from pydantic import BaseModel, ConfigDict, Field
from starlette.concurrency import run_in_threadpool
from starlette.datastructures import QueryParams

from ...config import Settings
from ...errors import Busy, ParameterError
from ...export import build
from ...export.image import ImageRenderer
from ...integrate import budget
from ...views import VIEWS
from ...work import jobs
from ... import work
from ..deps import RendererDep, SettingsDep
from ..http.caching import cache_control
from ..http.guard import json_error, query_refusal
from ..http.query_route import read_query
from . import figures

router = APIRouter(prefix="/api/v1")

#: what a batch may ask for: the figures, by GET
PREFIX = "/api/v1/figures/"
MAX_REQUESTS = 16

#: an answer: (status, Cache-Control, JSON body or None, Retry-After or None)
Answer = tuple[int, str | None, bytes | None, str | None]


class BatchBody(BaseModel):
    """The GETs to answer, as paths with their queries (``/api/v1/figures/ndf?alpha=0.2``)."""
    model_config = ConfigDict(extra="forbid")
    requests: list[str] = Field(min_length=1, max_length=MAX_REQUESTS,
                                description=f"paths under {PREFIX} with their queries")


def _format(path: str) -> tuple[str, str, str]:
    """(view, format, name) of a figure path: ``/api/v1/figures/ndf.csv`` → ndf, csv."""
    name = path.removeprefix(PREFIX)
    view, _, fmt = name.partition(".")
    return view, fmt or "json", name


def _judge(request: Request, settings: Settings, path: str, query: str):
    """The entry's (view, format, query model), or the exception its GET answers with:
    the guard's refusal as an Answer, or a validation or lookup error."""
    view_name, fmt, name = _format(path)
    if view_name not in VIEWS or fmt not in figures.FORMATS or "/" in name:
        try:
            figures.unknown_figure(name)
        except Exception as exc:        # the 404 (or 405) its GET answers
            return exc
    refusal = query_refusal(request.app, settings, path, "GET", query.encode("ascii"))
    if refusal is not None:
        return (refusal.status, "no-store",
                json_error(refusal.status, refusal.loc, refusal.message, refusal.kind)[1], None)
    view = VIEWS[view_name]
    model = build.image_query(view) if fmt in figures.IMAGES else build.export_query(view)
    try:
        return view, fmt, read_query(model, QueryParams(query))
    except RequestValidationError as exc:
        return exc


def _one(view, fmt: str, q, settings: Settings, renderer: ImageRenderer) -> Response:
    """The entry's answer, by the function its GET route calls."""
    if fmt == "json":
        return Response(figures.figure_body(view, q, settings), media_type=figures.MEDIA["json"])
    if fmt == "csv":
        return figures.csv_body(view, q, settings)
    return figures.image_body(view, fmt, q, settings, renderer)


def _compute(entries: list, settings: Settings, renderer: ImageRenderer) -> list:
    """Each (view, format, query)'s Response and whether the budget cut it, or the
    exception it raised: one after another under the request's one budget. Each entry
    sees that budget's clock and limit (so a cost that could never fit is a 413 and one
    that does not fit what is left a 503, app/integrate/cost.py), its own cuts counted."""
    shared = budget.current()
    with budget.limit(settings.max_seconds) as opened:
        shared = shared or opened
        out = []
        for view, fmt, q in entries:
            if out and shared.elapsed() >= shared.seconds:   # the first runs, as its GET
                out.append(Busy(f"this batch spent its time budget (BRDF_MAX_SECONDS="
                                f"{shared.seconds:g}) before this entry: retry it",
                                retry_after=math.ceil(shared.seconds), what="time budget"))
                continue
            with budget.limit(shared.seconds) as own:
                own.start = shared.start
                try:
                    out.append((_one(view, fmt, q, settings, renderer), bool(own.notes)))
                except Exception as exc:     # answered by the application's handler for it
                    out.append(exc)
            shared.notes.extend(own.notes)
    return out


async def _handled(request: Request, exc: Exception) -> Answer:
    """The answer the application's handler for ``exc`` gives (as Starlette finds it: the
    nearest class in the exception's MRO; an HTTPException by FastAPI's own)."""
    handlers = request.app.exception_handlers
    handler = next((handlers[c] for c in type(exc).__mro__ if c in handlers), None)
    if handler is None:            # the application handles Exception: not reached
        raise exc
    response = await handler(request, exc)
    return (response.status_code, response.headers.get("cache-control", "no-store"),
            response.body if response.media_type == "application/json" or
            response.headers.get("content-type", "").startswith("application/json") else None,
            response.headers.get("retry-after"))


async def _heavy_answer(request: Request, path: str, outcome, settings: Settings) -> Answer:
    """A heavy entry's answer from what the pool's job returned for it (jobs.views)."""
    if isinstance(outcome, Exception):
        return await _handled(request, outcome)
    if outcome[0] == "ok":
        _, body, media, cut = outcome
        return _answer(path, Response(body, media_type=media), cut, settings.cache_max_age)
    error = Busy(*outcome[1:]) if outcome[0] == "busy" else ParameterError(*outcome[1:])
    return await _handled(request, error)


def _answer(path: str, response: Response, cut: bool, max_age: int) -> Answer:
    is_json = response.media_type == "application/json"
    # an answer cut short by the time budget is not to be kept (as the guard says)
    return (response.status_code, "no-store" if cut else cache_control(path, max_age),
            response.body if is_json else None, None)


@router.post("/batch", tags=["figures"], response_class=Response,
             summary="Several figures in one request",
             openapi_extra={"requestBody": {"content": {"application/json": {"example": {
                 "requests": ["/api/v1/figures/ndf?alpha=0.2", "/api/v1/figures/g1?alpha=0.2"]}}}}},
             responses={200: {"content": {"application/json": {"example": {"responses": [
                 {"status": 200, "cache": "public, max-age=3600", "body": {"data": [], "layout": {}}},
                 {"status": 422, "cache": "no-store", "body": {"detail": [{"loc": ["query", "alpha"],
                                                                        "msg": "…", "type": "…"}]}},
                 {"status": 503, "cache": "no-store", "retry_after": 2, "body": {"detail": [
                     {"loc": ["query", "time budget"], "msg": "…: retry", "type": "busy"}]}}]}}}}})
async def batch(request: Request, settings: SettingsDep, renderer: RendererDep,
                body: BatchBody) -> Response:
    targets = [urlsplit(target) for target in body.requests]
    for k, (target, parts) in enumerate(zip(body.requests, targets)):
        if parts.scheme or parts.netloc or not parts.path.startswith(PREFIX) or parts.fragment:
            raise ParameterError(f"requests[{k}]", f"requests[{k}]: {target[:80]!r} is not a path under "
                                 f"{PREFIX} (a batch answers the figures' GETs only)", loc="body")
        if not target.isascii():
            raise ParameterError(f"requests[{k}]", f"requests[{k}]: {target[:80]!r} has characters "
                                 "a URL does not: percent-encode them", loc="body")
    answers: list[Answer | None] = [None] * len(targets)
    judged = []                  # (k, view, format, query) to compute
    for k, parts in enumerate(targets):
        verdict = _judge(request, settings, parts.path, parts.query)
        if isinstance(verdict, Exception):
            answers[k] = await _handled(request, verdict)
        elif len(verdict) == 4:  # the guard's refusal
            answers[k] = verdict
        else:
            judged.append((k, *verdict))
    # a view with a cost model runs in the heavy pool (one job for them all, after the
    # others, under the same budget); the rest in a worker thread
    heavy = [entry for entry in judged if work.is_heavy(entry[1].name)]
    light = [entry for entry in judged if entry not in heavy]
    for entry in list(heavy):    # what can never be answered: its 422 now, no pool place
        try:
            jobs.judge(entry[1].name, entry[3], settings)
        except ParameterError as exc:
            heavy.remove(entry)
            answers[entry[0]] = await _handled(request, exc)
    computed = await run_in_threadpool(_compute, [entry[1:] for entry in light], settings, renderer)
    for (k, *_), result in zip(light, computed):
        if isinstance(result, Exception):
            answers[k] = await _handled(request, result)
        else:
            answers[k] = _answer(targets[k].path, *result, settings.cache_max_age)
    if heavy:
        try:
            outcomes = await work.run_heavy(jobs.views, [
                (view.name, fmt, jobs.query_state(q)) for k, view, fmt, q in heavy], settings)
        except (Busy, ParameterError) as exc:      # not admitted, or cut: each entry says so
            outcomes = [exc] * len(heavy)
        for (k, view, fmt, q), outcome in zip(heavy, outcomes):
            if not isinstance(outcome, Exception) and outcome[0] == "ok" and outcome[2] == "figure":
                # an image: its figure computed in the pool, drawn here within what is left
                try:
                    drawn = await run_in_threadpool(figures.rendered, view, fmt, q, outcome[1], renderer, 0.0)
                    outcome = ("ok", drawn.body, drawn.media_type, outcome[3])
                except Exception as exc:        # answered by the application's handler for it
                    outcome = exc
            answers[k] = await _heavy_answer(request, targets[k].path, outcome, settings)
    out = [b'{"status":%d,"cache":%s,"body":%s%s}'
           % (status, json.dumps(cache).encode(), content if content is not None else b"null",
              b',"retry_after":%d' % int(retry) if status == 503 and retry and retry.isdigit() else b"")
           for status, cache, content, retry in answers]
    return Response(b'{"responses":[' + b",".join(out) + b"]}", media_type="application/json",
                    headers={"Cache-Control": "no-store"})
