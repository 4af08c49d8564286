"""``POST /api/v1/fit``: a model fitted to a data set (least squares), within the
request's time budget. The work is in app/fit."""
from typing import Annotated, Any, Literal, Optional

from fastapi import APIRouter, Body, Response
from pydantic import BaseModel, ConfigDict, Field
from starlette.concurrency import run_in_threadpool

from ... import work
from ...fit import run as fitting
from ...fit.problem import MEASURES
from ...integrate import budget
from ...work import jobs
from ..deps import DatasetsDep, Route
from ..encode import json_response

router = APIRouter(prefix="/api/v1", route_class=Route)


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


