"""``GET/POST /api/v1/eval``: the BRDF's terms at given direction pairs (i = light l,
o = view v); the lists' sizes judged against the settings' limits before any work."""
from typing import Annotated

import numpy as np
from fastapi import APIRouter, Body, Query

from ... import quantities
from ...errors import ParameterError
from ...views import schemas
from ..deps import Route, SettingsDep
from ..encode import json_response

router = APIRouter(prefix="/api/v1", tags=["data"], route_class=Route)

DIRECTIONS = ("theta_i_deg", "phi_i_deg", "theta_o_deg", "phi_o_deg")


def _evaluate(q: schemas.EvalQuery, limit: int, status: int, env: str, loc: str = "query"):
    lists = {name: getattr(q, name) for name in DIRECTIONS}
    sizes = {name: len(v) for name, v in lists.items()}
    for name, size in sizes.items():
        if size == 0:
            raise ParameterError(name, f"{name} is empty: give at least one value", loc=loc)
        if size > limit:
            raise ParameterError(name, f"{name} has {size} values; the limit is {limit} (setting {env})",
                                 status=status, loc=loc)
    n = max(sizes.values())
    for name, size in sizes.items():
        if size not in (1, n):
            raise ParameterError(name, f"{name} has {size} values but another list has {n}: "
                                       "lists must have equal length, or one value to broadcast", loc=loc)
    q.check(loc)
    spec = schemas.spec_of(q)
    arrays = {k: np.asarray(v, dtype=float) for k, v in lists.items()}
    if q.precision == "float32":     # explicit only: float64 is the default (the reference)
        return json_response(quantities.evaluate_float32(
            spec.brdf(), arrays["theta_i_deg"], arrays["phi_i_deg"],
            arrays["theta_o_deg"], arrays["phi_o_deg"], tuple(dict.fromkeys(q.quantities)), loc=loc))
    return json_response(quantities.evaluate(
        spec.brdf(), arrays["theta_i_deg"], arrays["phi_i_deg"],
        arrays["theta_o_deg"], arrays["phi_o_deg"], tuple(dict.fromkeys(q.quantities))))


@router.get("/eval", summary="BRDF terms at direction pairs (i = light l, o = view v)",
            description="f, D(h), G1(l,h), G1(v,h), G2, F(v·h). A divergence (f where both "
                        "directions graze) is null.")
def eval_get(settings: SettingsDep, q: Annotated[schemas.EvalQuery, Query()]):
    return _evaluate(q, settings.max_query_list, 422, "BRDF_MAX_QUERY_LIST")


@router.post("/eval", summary="BRDF terms for a large batch, as a JSON body")
def eval_post(settings: SettingsDep, q: Annotated[schemas.EvalQuery, Body(openapi_examples={
        "two pairs": {"summary": "GGX α=0.2, two direction pairs",
                      "value": {"ndf": "ggx", "alpha": 0.2, "theta_i_deg": [30, 60], "phi_i_deg": [0],
                                "theta_o_deg": [30, 60], "phi_o_deg": [180], "quantities": ["f", "D"]}}})]):
    return _evaluate(q, settings.max_batch, 413, "BRDF_MAX_BATCH", loc="body")
