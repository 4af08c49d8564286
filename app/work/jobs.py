"""The heavy routes' work as module-level functions of plain data, run in the pool's
worker processes (pool.py): an upload's parsing and summary, a view with a cost model
(costs.py) as figure JSON, CSV or data, the model's exports, a fit, a batch's heavy
entries. Each runs under the request's budget, opened by the pool in the worker, and
checks its predicted cost there before it starts (costs.py): 413 if it can never fit,
503 if it does not fit what is left.

A query travels as its validated values (:func:`query_state`) and is rebuilt here as
the same model without validating again (the dynamic query models cannot be pickled;
their values can), so the worker computes exactly what the route judged.
"""
from __future__ import annotations

import orjson

from ..config import Settings
from ..datasets import formats, summary, tabulate
from ..errors import Busy, ParameterError
from ..export import build
from ..export.jsonable import OPTIONS, jsonable
from ..fit import run as fitting
from ..integrate import budget
from ..views import VIEWS, run, vary
from ..views.pipeline import refuse
from ..model import make_spec
from . import costs

#: what a route sends for its query: (field values, the names given in the request)
QueryState = tuple[dict, set]


def query_state(q) -> QueryState:
    """A validated query model's values and the names the request gave: plain data
    (numbers, strings, lists) a worker rebuilds the same query from (:func:`rebuilt`)."""
    return {**q.__dict__, **(q.__pydantic_extra__ or {})}, set(q.model_fields_set)


def rebuilt(model, state: QueryState):
    """``model`` holding ``state``'s values as they were validated in the server."""
    values, given = state
    return model.model_construct(_fields_set=given, **values)


def upload(content: bytes, fmt: str | None) -> tuple:
    """(data, summary) of an uploaded file."""
    data = formats.load(content, fmt)
    budget_check("file", "this upload's summary")
    return data, summary.summarize(data)


def budget_check(param: str, what: str) -> None:
    """Stop (503) once the request's budget is spent: between an upload's parsing and
    its summary, between a batch's entries."""
    b = budget.current()
    if b is not None and b.elapsed() > b.seconds:
        raise Busy(f"{what} ran out of BRDF_MAX_SECONDS={b.seconds:g} (the server is busy): "
                   "retry", retry_after=int(b.seconds), what="time budget")


def judge(view_name: str, q, settings: Settings) -> None:
    """The refusals that cost nothing, made in the server before a pool place is taken:
    a family the view does not draw, an albedo method it does not take, the view's own
    rules (each query of a ``vary``). A request that can never be answered gets its 422
    at once, never a 503 to retry because the pool is busy."""
    v = VIEWS[view_name]
    expanded = vary.expand(v, q)
    for one in expanded[0] if expanded else [q]:
        refuse(v, one)
        v.check(one, settings)


def view(view_name: str, fmt: str, state: QueryState, settings: Settings):
    """One view's answer (fmt: json = figure, csv, data = the arrays) and its media type,
    its cost checked first (costs.require_view); fmt svg or png: the figure to render
    (a dict: the server's renderer draws it)."""
    v = VIEWS[view_name]
    model = {"data": v.query, "svg": build.image_query(v), "png": build.image_query(v)}.get(
        fmt) or build.export_query(v)
    q = rebuilt(model, state)
    costs.require_view(v, q, settings)
    if fmt == "data":
        return orjson.dumps(jsonable(run(v, q, settings).data), option=OPTIONS), "application/json"
    if fmt in ("svg", "png"):
        build.check_image_size(q, settings)
    produced = build.produce(v, q, settings)
    if fmt in ("svg", "png"):
        return produced.figure
    if fmt == "csv":
        return produced.csv().encode(), "text/csv; charset=utf-8"
    return build.figure_json(produced).encode(), "application/json"


def views(entries: list[tuple[str, str, QueryState]], settings: Settings) -> list[tuple]:
    """A batch's heavy entries (view, fmt, query state), one after another under the request's
    one budget: each ("ok", body, media type, cut) (an image's figure with the media type
    "figure", for the server's renderer) or its error as pool.py returns one
    (an entry that no longer fits what is left is a 503, the rest still run)."""
    b = budget.current()
    out = []
    for view_name, fmt, state in entries:
        notes = len(b.notes) if b is not None else 0
        try:
            answer = view(view_name, fmt, state, settings)
            body, media = (answer, "figure") if isinstance(answer, dict) else answer
            out.append(("ok", body, media, b is not None and len(b.notes) > notes))
        except Busy as exc:
            out.append(("busy", exc.message, exc.retry_after, exc.what))
        except ParameterError as exc:
            out.append(("parameter", exc.param, exc.message, exc.status, exc.loc))
    return out


def model_csv(values: dict, n_theta: int, n_phi: int) -> bytes:
    """The model's samples CSV, its cost checked first (costs.require_samples_csv)."""
    import numpy as np
    brdf = make_spec(**values).brdf()
    theta, phi = np.linspace(0.0, 90.0, n_theta), np.arange(n_phi) * 360.0 / n_phi
    costs.require_samples_csv(brdf, n_theta, n_phi)
    return tabulate.samples_csv(brdf, theta, phi).encode()


def model_merl(values: dict) -> bytes:
    """The model's MERL .binary (tabulate checks its own cost)."""
    return tabulate.merl_bytes(make_spec(**values).brdf())


def fit(data, model: dict, free: list, measure: str, channel, seconds: float, max_points: int,
        fit_all: bool) -> dict:
    """A fit (or every NDF's), within ``seconds`` of its own."""
    return (fitting.fit_all if fit_all else fitting.fit)(data, model, free, measure, channel,
                                                         seconds, max_points)



def warm_up() -> None:
    """Bring a new pool process to its working size as it starts: numba and LLVM with the
    default model's loops (~120 MB resident, which the first job running compiled loops
    otherwise loads — a replaced process then stepped inside a later job), and the
    figure modules the views' answers use."""
    from .. import kernels
    from ..figures import sphere_image  # noqa: F401  (plotly's validators come with it)
    kernels.compile_now(make_spec().brdf(), "f")
