"""The speed-against-accuracy view: each albedo method over a range of budgets, its
error against a tight reference versus evaluations and seconds (app/analysis/tradeoff.py)."""
from __future__ import annotations

from typing import Annotated, Literal, Optional

import numpy as np
from pydantic import BeforeValidator, Field

from ..config import Settings
from ..analysis import tradeoff
from ..figures.tradeoff import tradeoff_figure
from ..integrate.albedo import max_evaluations
from . import schemas
from ..errors import ParameterError
from .view import View, limit

#: Largest max_budget the schema admits; the setting BRDF_MAX_TRADEOFF_SAMPLES is the
#: limit that applies (checked with a message naming it).
MAX_BUDGET_SCHEMA = 2 ** 20

Method = Literal[tradeoff.METHODS]


class TradeoffQuery(schemas.ModelQuery):
    quantity: Annotated[Literal[tradeoff.QUANTITIES], Field(
        description="what is integrated: only the directional albedo E(μ) for now")] = "albedo"
    methods: Annotated[Optional[list[Method]], BeforeValidator(schemas._split_commas), Field(
        description="methods to run, comma-separated: " + ", ".join(tradeoff.METHODS)
                    + "; default all that apply to the model (those that do not are listed "
                      "in not_applicable with the reason)")] = None
    mu: Annotated[Optional[schemas.MuList], Field(
        description="cosines μ in [0, 1], comma-separated; the error is the max over them; "
                    "default 9 evenly spaced, 0 and 1 included")] = None
    phi_deg: Annotated[schemas.Phi, Field(description="azimuth of v (matters when anisotropic)")] = 0.0
    max_budget: Annotated[int, Field(
        ge=tradeoff.MC_SAMPLES_START, le=MAX_BUDGET_SCHEMA,
        description=f"largest budget: Monte Carlo samples per μ ({tradeoff.MC_SAMPLES_START}·4^k up "
                    f"to it) and Gauss orders ({', '.join(map(str, tradeoff.QUADRATURE_ORDERS))} "
                    "up to it); at most the setting BRDF_MAX_TRADEOFF_SAMPLES")] = \
        tradeoff.DEFAULT_MAX_BUDGET
    seed: Annotated[int, Field(ge=0, le=2 ** 63 - 1,
                               description="seed of the Monte Carlo points")] = 0


class TradeoffFigureQuery(TradeoffQuery):
    x: Annotated[Literal["evaluations", "seconds"], Field(
        description="horizontal axis: integrand evaluations or wall-clock seconds")] = "evaluations"


def _check(q, s: Settings):
    if q.methods is not None and len(q.methods) == 0:
        raise ParameterError("methods", "methods must name at least one of " + ", ".join(tradeoff.METHODS))
    if q.mu is not None and len(q.mu) == 0:
        raise ParameterError("mu", "mu must hold at least one value in [0, 1]")
    count = len(q.mu) if q.mu is not None else len(tradeoff.DEFAULT_MU)
    limit("mu", count, s.max_albedo_points, "BRDF_MAX_ALBEDO_POINTS")
    limit("max_budget", q.max_budget, s.max_tradeoff_samples, "BRDF_MAX_TRADEOFF_SAMPLES")
    # the reference is the refining quadrature: the albedo view's worst case
    worst = max_evaluations(schemas.spec_of(q).brdf(), count)
    if worst > s.max_evaluations:
        raise ParameterError("mu", f"the reference at {count} μ values may need up to {worst:.3g} "
                               f"integrand evaluations; the limit is {s.max_evaluations:.3g} "
                               "(setting BRDF_MAX_EVALUATIONS): ask for fewer")


def _compute(spec, q) -> dict:
    mu = q.mu if q.mu is not None else tradeoff.DEFAULT_MU
    data = tradeoff.tradeoff(spec.brdf(), spec.key(), mu,
                             float(np.deg2rad(q.phi_deg)), q.methods, q.max_budget, q.seed)
    if "note" in data:
        data["note"] += " (setting BRDF_MAX_SECONDS)"
    return data


VIEW = View(
    "tradeoff", "Speed against accuracy",
    "Albedo error against cost: each method (quadrature, Monte Carlo, table) over a range "
    "of budgets, max |E − E_ref| over μ versus evaluations and seconds.",
    TradeoffQuery, TradeoffFigureQuery, _compute,
    lambda data, spec, q: tradeoff_figure(data, spec.values, getattr(q, "x", "evaluations")),
    _check,
    overlayable=True, layout="wide")
