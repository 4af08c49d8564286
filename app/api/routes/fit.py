"""``POST /api/v1/fit``: a model fitted to a data set (least squares), within the
request's time budget. The work is in app/fit."""
from typing import Annotated

from fastapi import APIRouter, Body, Response
from starlette.concurrency import run_in_threadpool

from ... import work
from ...fit.body import FitBody
from ...integrate import budget
from ...work import jobs
from ..deps import DatasetsDep, Route
from ..encode import json_response

router = APIRouter(prefix="/api/v1", route_class=Route)


#: of the request's time budget, the part a fit may take: the rest encodes the answer
FIT_SHARE = 0.8


@router.post("/fit", tags=["datasets"], summary="Fit a model to a data set (least squares)",
             description="Answers the fitted parameters with standard errors from the Jacobian "
                         "at the optimum, the residual, evaluations and seconds, and `model`: the "
                         "whole fitted model, to send to any endpoint as it is.",
             responses={404: {"description": "No data set has the id in `data`"},
                        410: {"description": "The data set in `data` has expired (evicted or deleted)"}})
async def fit(datasets: DatasetsDep, body: Annotated[FitBody, Body(openapi_examples={"GGX to a MERL file": {
        "summary": "α, F0 and kd of GGX, red channel, log measure",
        "value": {"data": "3e071955855cb1a4a828bf3b009a1d2b", "model": {"ndf": "ggx", "alpha": 0.3},
                  "free": ["alpha", "f0", "kd"], "measure": "log", "channel": "r"}}})]) -> Response:
    seconds = body.seconds
    request_budget = budget.current()
    if request_budget is not None:
        seconds = min(seconds, FIT_SHARE * (request_budget.seconds - request_budget.elapsed()))
    data, _ = await run_in_threadpool(datasets.get, body.data)
    # in the heavy pool: its own seconds bound it, the pool's cut the rest
    result = await work.run_heavy(jobs.fit, data, body.model, body.free, body.measure,
                                  body.channel, seconds, body.max_points, body.fit_all,
                                  cost=seconds)
    return json_response({"data": body.data, **result})


