"""What a fit is asked: the body of ``POST /api/v1/fit`` and the options of the CLI's
``fit`` command (app/cli/data.py), one model for both."""

from typing import Any, Literal, Optional

from pydantic import BaseModel, ConfigDict, Field

from . import run as fitting
from .problem import MEASURES


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
