"""The checks view: the identities a microfacet model must satisfy computed numerically
for the current model, each next to the value it must have (app/analysis/checks.py),
drawn as a table."""
from __future__ import annotations

from typing import Annotated, Literal, Optional

from pydantic import BeforeValidator, Field

from ..analysis import checks
from ..figures.checks import checks_figure
from ..config import Settings
from . import schemas
from ..errors import ParameterError
from .view import View

#: Largest θ of v: at 90° (μ_v = 0) rows 2–4 are 0 = 0 and 0/0. A closed bound (not
#: θ < 90) so that the page, which shows numeric fields with both bounds, offers it.
THETA_MAX_DEG = 89.9

RowId = Literal[checks.ROW_IDS]


class ChecksQuery(schemas.ModelQuery):
    theta_deg: Annotated[float, Field(
        ge=0.0, le=THETA_MAX_DEG, examples=[60.0],
        description=f"polar angle of the view direction v in degrees, [0, {THETA_MAX_DEG}]")] = 60.0
    phi_deg: Annotated[float, Field(
        ge=-360.0, le=360.0, examples=[0.0],
        description="azimuth of v in degrees, [-360, 360] (matters when anisotropic)")] = 0.0
    ids: Annotated[Optional[list[RowId]], BeforeValidator(schemas._split_commas), Field(
        description="rows to compute, comma-separated, of " + ", ".join(checks.ROW_IDS)
                    + "; default all", json_schema_extra={"minItems": 1},
        examples=[["3", "4"]])] = None


def _check(q, s: Settings):
    if q.ids is not None and len(q.ids) == 0:
        raise ParameterError("ids", "ids must name at least one row of " + ", ".join(checks.ROW_IDS))


VIEW = View(
    "checks", "Identity checks",
    "The identities every microfacet model must satisfy (normalisation, projected area, "
    "Smith's G1, the white furnace, energy) computed for the model and a view direction, "
    "each next to the value it must have, with error and cost.",
    ChecksQuery, ChecksQuery,
    lambda spec, q: checks.checks(spec, q.theta_deg, q.phi_deg, q.ids),
    lambda data, spec, q: checks_figure(data, spec.values),
    _check,
    layout="wide")
