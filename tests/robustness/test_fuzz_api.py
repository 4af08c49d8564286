"""Schemathesis, driven by /openapi.json, against the app in-process.

Every operation the schema lists — the views, their figures and exports, /eval (GET and
POST), the meta routes, the embeds — so a new endpoint is fuzzed as soon as it exists.

Phases: *coverage* (deterministic: each parameter at its bounds, just outside them, of
the wrong type, missing, duplicated, plus methods the path does not allow) for every
operation outside /api/v1/figures/, a data set's overlays and the MERL export — a figure,
an overlay or an export takes its view's query (whose edges the data route's coverage
walks) plus a display option or two. The shared model parameters are walked whole on
/eval (MODEL_WALKERS); elsewhere only their edges and choices are sent, and no identical
request twice (:func:`worth_sending`); and *fuzzing*
(random, MAX_EXAMPLES per operation — IMAGE_EXAMPLES for PNG/SVG, each rendered in
Chromium — positive and negative) for all.

Checks: every check schemathesis has, plus four of ours (below): no 5xx but a 503 that
says when to retry (in place of schemathesis' own, which refuses that documented answer
too), no NaN or Infinity in a JSON body, no trace or file path in any body, and a 422 or
413 always names a parameter.

Positive cases are made consistent with the rules an OpenAPI query schema cannot state
before they are sent (:func:`consistent`), so ``positive_data_acceptance`` stays strict —
every consistent, schema-valid request must succeed:

* a choice parameter only with its choice, a masking only with the NDFs it applies to:
  :func:`app.model.make_spec` is the oracle — a parameter it names is dropped; likewise
  a view's own ``check`` (which runs before any work) for the view's rules (a sampler
  only with the NDFs it can sample);
* list parameters broadcast only at equal length (or one value): lists are cut to the
  shortest;
* sizes (integers: n, n_theta, …) small, so grids stay under the size limits that
  depend on products (n_theta × n_phi) and the run stays short; the limits themselves
  are tested by hand (test_hardening.py).

The exports, the overlays and /samples are the exception: ``vary``/``values`` must come
together, one label per model, the sampler must support the NDF — rules the schema
cannot state and make_spec does not know — so those operations run without
``positive_data_acceptance`` (every other check applies).

The app runs with BRDF_MAX_SECONDS = FUZZ_SECONDS: a case at tol = 1e-7 is cut, not
waited for, and the cut path is fuzzed too.
"""
from __future__ import annotations

from pydantic import BaseModel, ValidationError

import importlib
import json
import pkgutil
import re
import time
import typing

import pytest
import schemathesis
from fastapi import APIRouter
from fastapi.routing import APIRoute
from schemathesis.config import SchemathesisConfig

import app.api
from tests import heavy_pool
from app.model import DEFAULT as DEFAULT_FAMILY, families
import app.api.routes
from app.views import schemas
from tests.finite import finite_json as parse_finite
from app.errors import ParameterError
from app.views import VIEWS
from app.config import Settings
from app.main import create_app
from app.model import make_spec

#: random examples per operation in the fuzzing phase (the coverage phase adds its own
#: deterministic cases, ~100–400 per operation)
# Random examples per operation, on top of the coverage phase that already walks every
# parameter's edges. 25 made the whole suite 17 min on a loaded 2-core machine (CI's
# limit is 15); 5 keeps the random phase.
MAX_EXAMPLES = 5
#: the app's time budget here (BRDF_MAX_SECONDS): a quarter of a second cuts the slow cases
#: (tol = 1e-7, large grids) early, so the cut path is what they fuzz; at 0.5 the three slowest
#: operations (materials/fresnel, advise, sphere: ~100-200 coverage cases each) spent most of
#: their time waiting out the budget
FUZZ_SECONDS = 0.25
#: sizes and list lengths of positive cases
SIZE_CAP, LIST_CAP = 12, 6
#: random examples per image export (each renders in Chromium: 0.3–3 s); every view's
#: SVG and PNG are also rendered and checked in tests/export/test_images.py
IMAGE_EXAMPLES = 2
#: operations outside the views and /eval: the file exports (figure query + vary,
#: values, width, height, scale) and the overlays (POST a list of models with labels)
NOT_A_VIEW = r"^/api/v1/figures/[^/]+\.[a-z]+$"
OVERLAY = r"^/api/v1/figures/[^/.]+$"
#: the figure of a view takes the view's query plus a display option or two: the data
#: route's coverage already walks every shared parameter's edges
FIGURE = r"^/api/v1/figures/"
#: a measured data set drawn over a view: /api/v1/datasets/{data_id}/[figures/]{view}
OVERLAY_OF_DATA = r"^/api/v1/datasets/\{data_id\}/(figures/)?[a-z0-9_]+$"

CONFIG = SchemathesisConfig.from_dict({
    "seed": 20240611,
    "generation": {"mode": "all", "max-examples": MAX_EXAMPLES, "database": "none"},
    "checks": {"not_a_server_error": {"enabled": False}},     # no_server_error_but_busy
    "phases": {
        "examples": {"enabled": False},          # the schema has none
        "stateful": {"enabled": False},          # no links: the API is stateless
        "coverage": {"enabled": True, "generate-duplicate-query-parameters": True},
        "fuzzing": {"enabled": True},
    },
    "operations": [
        {"include-path-regex": FIGURE, "phases": {"coverage": {"enabled": False}}},
        # a data set's overlays take their view's query (walked on the view's own route),
        # and the MERL export takes the model alone (walked on /eval) at ~0.6 s a request
        {"include-path-regex": OVERLAY_OF_DATA, "phases": {"coverage": {"enabled": False}}},
        {"include-path-regex": r"^/api/v1/export/model\.binary$", "phases": {"coverage": {"enabled": False}}},
        {"include-path-regex": NOT_A_VIEW,
         "checks": {"positive_data_acceptance": {"enabled": False}}},
        {"include-path-regex": OVERLAY, "include-method": "POST",
         "checks": {"positive_data_acceptance": {"enabled": False}}},
        {"include-path-regex": r"\.(png|svg)$",
         "generation": {"max-examples": IMAGE_EXAMPLES}},
        # /samples: the sampler must support the NDF (vndf: GGX and Beckmann only), a
        # rule neither the schema nor make_spec states; its 422 names ``sampler``.
        {"include-path-regex": r"/samples", "checks": {"positive_data_acceptance": {"enabled": False}}},
        # a LUT's time is predicted from its first rows, on this machine, now: under the
        # 0.5 s budget a loaded machine rightly refuses even size 12 (413 naming size)
        {"include-path-regex": r"^/api/v1/lut$",
         "checks": {"positive_data_acceptance": {"expected-statuses": [
             "2XX", "3XX", "401", "403", "404", "409", "413", "429", "5XX"]}}},
        # the one documented operation of the figures' format twins: width, height and
        # scale size an image (svg, png) and are refused, naming them, for csv and json — a
        # rule per value of {format} that one operation's parameters cannot state (every
        # other check, 5xx included, still applies)
        {"include-path-regex": r"\{view\}\.\{format\}",
         "checks": {"positive_data_acceptance": {"enabled": False}}},
        # measured data sets: a schema-valid body (random bytes) is rightly a 422 "not a
        # known format"
        {"include-path-regex": r"^/api/v1/(datasets|fit|export/model)",
         "checks": {"positive_data_acceptance": {"enabled": False}}},
    ],
})

APP = create_app(Settings(max_seconds=FUZZ_SECONDS))
schema = schemathesis.openapi.from_asgi("/openapi.json", APP, config=CONFIG)


@pytest.fixture(scope="module", autouse=True)
def heavy_pool_started():
    """The process's heavy-work pool (one for the run: tests/conftest.py) started before
    the first operation, as a server's is: with a quarter second of budget, a heavy
    operation met while its worker starts is refused, and its own work goes unfuzzed."""
    heavy_pool.started()


#: filled by the test, reported by conftest.py at the end of the run
CALLS: dict[str, int] = {}
SECONDS: dict[str, float] = {}


# ----------------------------------------------------------------------------- checks

@schemathesis.check
def no_server_error_but_busy(ctx, response, case):
    """No 5xx but the API's 503 for a busy machine, which says when to retry (the
    built-in not_a_server_error, off below, would refuse that documented answer too)."""
    if response.status_code >= 500:
        assert response.status_code == 503 and "retry-after" in {h.lower() for h in response.headers}, \
            f"server error {response.status_code}: {response.content[:200]!r}"


@schemathesis.check
def finite_json(ctx, response, case):
    """No NaN or ±Infinity anywhere in a JSON body (a divergence is null)."""
    if "json" in response.headers.get("content-type", [""])[0]:
        parse_finite(response.content)


#: a Python trace or a path into the source tree
LEAK = re.compile(rb"Traceback \(most recent call last\)|File \"/|/app/[a-z_/]+\.py|site-packages")


@schemathesis.check
def no_internal_details(ctx, response, case):
    """No stack trace or source path in any body, whatever the status."""
    match = LEAK.search(response.content)
    assert match is None, f"response leaks {match.group(0)!r}"


@schemathesis.check
def errors_name_a_parameter(ctx, response, case):
    """A 422 or a 413 says which parameter (``loc``) and why (``msg``)."""
    if response.status_code in (413, 422):
        detail = json.loads(response.content)["detail"]
        assert isinstance(detail, list) and detail, detail
        for item in detail:
            assert item["msg"] and len(item["loc"]) >= 1, item


# --------------------------------------------------------------------- positive cases

def _cap_sizes(values: dict, operation) -> None:
    for param in operation.query:
        d = param.definition.get("schema", {})
        if d.get("type") == "integer":
            small = max(SIZE_CAP, d.get("minimum", SIZE_CAP))
            v = values.get(param.name)
            if isinstance(v, list):          # a duplicated query parameter: size=32&size=32
                v = v[0] if v else None
            if isinstance(v, str) and v.isdigit():      # the coverage phase sends text
                v = int(v)
            if v is None or (isinstance(v, int) and not isinstance(v, bool) and v > small):
                values[param.name] = small
    _equal_lists(values)


def _equal_lists(values: dict) -> None:
    lengths = [len(v) for v in values.values() if isinstance(v, list) and v]
    if lengths:
        n = min(LIST_CAP, *lengths)
        for k, v in values.items():
            if isinstance(v, list):
                values[k] = v[:n]


def _drop_until_accepted(values: dict, refusal, what: str, required=frozenset()) -> None:
    """Drop parameters until ``refusal(values)`` (the name of the parameter an oracle
    refuses, or None) is None: the one it names, or — when it names one that was not
    given (alpha_y derived from roughness and anisotropy; the default sampler, which
    cannot sample the NDF given) or one the operation requires (material=gold with
    model=principled) — the first other given one whose removal changes its verdict."""
    for _ in range(len(values) + 1):
        named = refusal(values)
        if named is None:
            return
        if named in values and named not in required:
            del values[named]
            continue
        for k in [k for k in values if k not in required]:
            if refusal({x: v for x, v in values.items() if x != k}) != named:
                del values[k]
                break
        else:
            raise AssertionError(f"{what} refuses {named}; no given parameter explains it")


def _model_refusal(values: dict) -> str | None:
    given = {k: v for k, v in values.items() if k in schemas.ModelQuery.model_fields}
    try:
        make_spec(**schemas.model_values(schemas.ModelQuery(**given)))
    except ParameterError as e:
        return e.param
    except ValidationError as e:
        # a route's own field that shares a model field's name with another vocabulary
        # (the data sets' channel=F): the model's validation names it
        return next((x for x in e.errors()[0]["loc"] if isinstance(x, str)), None)
    return None


def _view_of(path: str):
    """The view and query model behind a data or figure route, or None."""
    m = re.fullmatch(r"/api/v1/(figures/)?([a-z0-9_]+)", path)
    view = VIEWS.get(m.group(2)) if m else None
    if view is None:
        return None
    return view, (view.figure_query if m.group(1) else view.query)


def _view_refusal(view, model):
    def refusal(values: dict) -> str | None:
        family = families().get(values.get("model") or DEFAULT_FAMILY)
        if family is not None and family.views(view.name) is not None:
            return "model"                       # a view the family declares it is not drawn by
        try:
            # the view's own query (a figure route also takes vary/values, checked by compare)
            view.check(model(**{k: v for k, v in values.items() if k in model.model_fields}),
                       APP.state.settings)
        except ParameterError as e:
            return e.param
        return None
    return refusal


#: every route of the API's routers (app.api.routes' modules each hold one ``router``)
_API_ROUTES = [r for name in pkgutil.iter_modules(app.api.routes.__path__)
               for router in [getattr(importlib.import_module(f"app.api.routes.{name.name}"), "router", None)]
               if isinstance(router, APIRouter) for r in router.routes if isinstance(r, APIRoute)]


def _query_model_of(path: str, method: str):
    """The pydantic query model of a route outside the views, when it states its own
    cross-parameter rules in a ``check`` method (the routes call it before any work)."""
    for route in _API_ROUTES:
        if route.path == path and method in route.methods:
            hints = typing.get_type_hints(route.endpoint, include_extras=True)
            for hint in hints.values():
                model = typing.get_args(hint)[0] if typing.get_origin(hint) is typing.Annotated else hint
                if isinstance(model, type) and issubclass(model, BaseModel) and hasattr(model, "check"):
                    return model
    return None


def _query_refusal(model):
    def refusal(values: dict) -> str | None:
        try:
            model(**{k: v for k, v in values.items() if k in model.model_fields}).check()
        except ParameterError as e:
            return e.param
        except ValidationError:
            return None             # the schema's own rules: not this oracle's to judge
        return None
    return refusal


def consistent(case) -> None:
    """Make a positive case obey the cross-parameter rules (module docstring)."""
    if isinstance(case.query, dict):
        _cap_sizes(case.query, case.operation)
        required = frozenset(p.name for p in case.operation.query if p.is_required)
        _drop_until_accepted(case.query, _model_refusal, "make_spec", required)
        found = _view_of(case.path)
        if found is not None:
            _drop_until_accepted(case.query, _view_refusal(*found), f"{case.path} check")
            # a dropped model= (a family the view does not draw) leaves its family's names
            _drop_until_accepted(case.query, _model_refusal, "make_spec", required)
        elif (model := _query_model_of(case.path, case.method.upper())) is not None:
            _drop_until_accepted(case.query, _query_refusal(model), f"{case.path} check")
    if isinstance(case.body, dict):
        _drop_until_accepted(case.body, _model_refusal, "make_spec")
        if (model := _query_model_of(case.path, case.method.upper())) is not None:
            _drop_until_accepted(case.body, _query_refusal(model), f"{case.path} check")
        _equal_lists(case.body)


# ------------------------------------------------------------------- what to send

#: the operations whose coverage phase walks every edge of the shared model parameters
#: (ModelQuery: the same pydantic model and make_spec behind every route)
MODEL_WALKERS = {"GET /api/v1/eval", "POST /api/v1/eval"}
#: elsewhere a shared parameter's coverage case is sent only when it puts the model at an
#: end of its range (the view's numbers at α → 0, γ → its bound) or makes a choice other
#: than a measured material (each view with each NDF, masking, G2, Fresnel): what a wrong
#: type, an out-of-range value or one of 110 materials does is decided by the shared
#: model before any view's code
EDGES = {"minimum_value", "maximum_value", "enum_value"}
#: positive requests already sent, after :func:`consistent`: identical ones answer alike,
#: and so, outside MODEL_WALKERS, do ones whose shared parameters name the same model
#: (``{'ndf': 'ggx'}`` and ``{}`` are both the default model: a view's code sees only the
#: model make_spec builds; 40 of a view's ~45 "required and optional" combinations were
#: the default model again, each answered in full)
SENT: set[tuple] = set()


def _model_key(case, query: dict):
    """The query with its shared model parameters replaced by the model they name (the
    query as it is where the model is refused: the refusal is what is tested)."""
    if f"{case.method} {case.path}" in MODEL_WALKERS:
        return query
    shared = {k: v for k, v in query.items() if k in schemas.ModelQuery.model_fields}
    try:
        spec = make_spec(**schemas.model_values(schemas.ModelQuery(**shared)))
    except (ParameterError, ValidationError):
        return query
    return {"model": spec.values, **{k: v for k, v in query.items() if k not in shared}}


def worth_sending(case) -> bool:
    """Whether this case tells something the run has not learnt yet (see MODEL_WALKERS)."""
    phase = case.meta.phase if case.meta is not None else None
    data = getattr(phase, "data", None)
    param = getattr(data, "parameter", None)
    if (param in schemas.ModelQuery.model_fields and f"{case.method} {case.path}" not in MODEL_WALKERS
            and (getattr(getattr(data, "scenario", None), "value", None) not in EDGES or param == "material")):
        return False
    if case.meta is not None and case.meta.generation.mode.is_positive:
        sent = (case.method, case.path, json.dumps(case.path_parameters, sort_keys=True, default=str),
                json.dumps(_model_key(case, case.query) if isinstance(case.query, dict) else case.query,
                           sort_keys=True, default=str),
                json.dumps(case.body, sort_keys=True, default=str))
        if sent in SENT:
            return False
        SENT.add(sent)
    return True


# ------------------------------------------------------------------------------- test

@schema.parametrize()
def test_api(case):
    if case.meta is not None and case.meta.generation.mode.is_positive:
        consistent(case)
    if not worth_sending(case):
        return
    key = f"{case.method} {case.path}"
    CALLS[key] = CALLS.get(key, 0) + 1
    t0 = time.perf_counter()
    try:
        case.call_and_validate()
    finally:
        SECONDS[key] = SECONDS.get(key, 0.0) + time.perf_counter() - t0
