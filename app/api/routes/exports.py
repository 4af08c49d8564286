"""The model as data files users load elsewhere: ``GET /api/v1/export/model.binary`` (MERL)
and ``GET /api/v1/export/model.csv`` (BRDF samples, the format POST /datasets reads)."""
from typing import Annotated

from fastapi import APIRouter, Query, Response
from pydantic import Field

from ... import work
from ...datasets import tabulate
from ...model import make_spec
from ...work import jobs
from ...views import schemas
from ..deps import Route

router = APIRouter(prefix="/api/v1", route_class=Route)


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
async def export_merl(q: Annotated[schemas.ModelQuery, Query()]) -> Response:
    values = schemas.model_values(q)
    make_spec(**values)                  # a bad model is a 422 here, before any queue
    content = await work.run_heavy(jobs.model_merl, values)
    return Response(content, media_type="application/octet-stream",
                    headers={"content-disposition": 'attachment; filename="model.binary"'})


@router.get("/export/model.csv", tags=["exports"], response_class=Response,
            summary="The model as a CSV of BRDF samples (the format POST /datasets reads)",
            description="n_theta² × n_phi rows; their time (evaluations and encoding) is "
                        "predicted before any work: 413 naming the n_phi that would fit.",
            responses={200: {"content": {"text/csv": {"example": ",".join(tabulate.SAMPLE_COLUMNS)}}},
                       413: {"description": "This table takes longer than BRDF_MAX_SECONDS"},
                       503: {"description": "Busy: Retry-After says when to retry"}})
async def export_samples(q: Annotated[SamplesExportQuery, Query()]) -> Response:
    values = schemas.model_values(q)
    make_spec(**values)
    text = await work.run_heavy(jobs.model_csv, values, q.n_theta, q.n_phi)
    return Response(text, media_type="text/csv",
                    headers={"content-disposition": 'attachment; filename="model.csv"'})


