"""Speed against accuracy: each albedo method run over a range of budgets, its E(μ)
compared with a tight reference (the quadrature refined to REFERENCE_TOL, cached).

Budget: the Gauss order N of the quadrature, samples per μ of Monte Carlo, one point for
the table (its build cost reported apart). Per point: max and RMS over μ of |E − E_ref|,
the method's own reported error, and the share of μ where the reported error covers the
true one (1 for a bound, ~0.68 for one standard error). Points run level by level across
the methods while the request's time budget affords them; a complete result is kept and
served again (``cached``). Details: docs/albedo.md §5.
"""
from __future__ import annotations

import time
from contextvars import ContextVar

import numpy as np

from ..physics.brdf import BRDF, CompensatedBRDF
from ..integrate import budget, tables
from ..integrate.tables.table import TABLE_N_R, TABLE_N_Y
from ..integrate.cache import Keyed, complete_only, freeze
from ..errors import ParameterError
from ..integrate.methods import MC_METHODS, albedo_by
from ..integrate.sampling import SAMPLERS

QUANTITIES = ("albedo",)
METHODS = ("quadrature", *MC_METHODS, "table")
#: Gauss orders N of the quadrature points (each compares N with 2N; 2·64 = 128 stays
#: within albedo.ORDER_MAX, the range where its error estimate was checked).
QUADRATURE_ORDERS = (4, 8, 16, 32, 64)
#: Samples per μ of the Monte Carlo points: 16 · 4^k (each ×4 halves the standard
#: error), up to the request's max_budget.
MC_SAMPLES_START, MC_SAMPLES_GROWTH = 16, 4
#: Largest samples per μ a request asks for unless it says otherwise (~0.1 s for the
#: four samplers at 9 μ on GGX, measured; bench/tradeoff.py).
DEFAULT_MAX_BUDGET = 16_384
#: Default cosines: 9 evenly spaced in [0, 1], both ends (grazing and normal) included.
DEFAULT_MU = tuple(np.linspace(0.0, 1.0, 9).tolist())
#: Target of the reference quadrature: 100× below the finest quadrature point's typical
#: error above the rounding floor, reached at order ≤ 96 for GGX α = 0.1 and 0.5 (measured
#: 6e-9 and 1.5e-9). Where albedo.ORDER_MAX does not reach it, the bound says so.
REFERENCE_TOL = 1e-8
#: References kept (each a few hundred bytes at ≤ BRDF_MAX_ALBEDO_POINTS μ values).
REFERENCE_CACHE_ENTRIES = 64
#: Complete results kept (a few kB each): the figure, the page's x toggle and the exports
#: of one state then show the same measurement (timings cannot be repeated exactly).
RESULT_CACHE_ENTRIES = 64
#: Time left in the budget that the table point needs to start: if the tables are not
#: built yet, its lookup builds them, which takes seconds (measured on the 2-core server:
#: 0.45 s for GGX to 7.8 s for exp_power per 32×32 table; two tables with Schlick). A
#: build that still runs out is cut by its own quadratures, which report the larger
#: error (tables.py). Under the fuzzer's 0.5 s budget the table point never starts.
TABLE_RESERVE_SECONDS = 2.0
TIMING = "single-run wall clock on a shared server: compare orders of magnitude, not percents"


#: Set by a cached function's body when it runs: tells its caller, in this thread, that
#: the result was computed now rather than found (cache_info counts every thread's hits).
_COMPUTED: ContextVar[list | None] = ContextVar("tradeoff_computed", default=None)


def _mark_computed() -> None:
    marks = _COMPUTED.get()
    if marks is not None:
        marks.append(True)


def _from_cache(function, *args) -> tuple[dict, bool]:
    """(a copy of ``function(*args)``, whether it came from its cache)."""
    marks: list = []
    token = _COMPUTED.set(marks)
    try:
        data = function(*args)
    finally:
        _COMPUTED.reset(token)
    return dict(data), not marks


def _single(brdf: BRDF) -> BRDF:
    return brdf.single() if isinstance(brdf, CompensatedBRDF) else brdf


def not_applicable(brdf: BRDF) -> dict[str, str]:
    """Method → why it does not apply to this model (absent: it applies)."""
    single = _single(brdf)
    out = {}
    for method, sampler in MC_METHODS.items():
        try:
            SAMPLERS[sampler].check(single)
        except ValueError as exc:
            out[method] = str(exc)
    if not all(lobe.ndf.isotropic for _, lobe in single.lobes()):
        out["table"] = "the E(μ, α) tables are for isotropic roughness only (alpha_y = alpha)"
    elif single.fresnel.schlick_basis() is None:
        out["table"] = (f"the tables hold F = 1 and the Schlick basis; fresnel="
                        f"{single.fresnel.name} is not tabulated")
    return out


def budgets(method: str, max_budget: int) -> list[int]:
    """The budgets of ``method`` up to ``max_budget``, smallest first."""
    if method == "quadrature":
        return [n for n in QUADRATURE_ORDERS if n <= max_budget]
    if method in MC_METHODS:
        out, n = [], MC_SAMPLES_START
        while n <= max_budget:
            out.append(n)
            n *= MC_SAMPLES_GROWTH
        return out
    return [TABLE_N_Y * TABLE_N_R]


def _cost_growth(method: str, previous: int, following: int) -> float:
    """Predicted time ratio of two budgets: Monte Carlo ∝ samples; the quadrature's
    nodes ∝ N² (N along u times ~N along ψ)."""
    ratio = following / previous
    return ratio * ratio if method == "quadrature" else ratio


@complete_only(REFERENCE_CACHE_ENTRIES)
def _reference_cached(model: Keyed, mu: tuple, phi: float) -> dict:
    _mark_computed()
    res = albedo_by(model.value, np.asarray(mu, dtype=float), phi, "quadrature",
                    tol=REFERENCE_TOL, average=False)
    err = np.asarray(res["E_error"], dtype=float)
    return freeze({"method": "quadrature", "tol": REFERENCE_TOL, "mu": np.asarray(mu),
                   "E": np.asarray(res["E"], dtype=float), "E_error": err,
                   "error": float(np.max(err)), "evaluations": int(res["evaluations"]),
                   "seconds": float(res["seconds"])})


def reference(brdf: BRDF, key, mu, phi: float = 0.0) -> tuple[dict, bool]:
    """(reference E(μ) with its bound and cost, whether it came from the cache).
    ``key``: hashable model values (equal keys, equal BRDFs)."""
    mu_key = tuple(float(m) for m in np.atleast_1d(mu))
    return _from_cache(_reference_cached, Keyed(brdf, key), mu_key, float(phi))


def _run(brdf: BRDF, mu, phi: float, method: str, n: int, seed: int) -> dict:
    if method == "quadrature":
        return albedo_by(brdf, mu, phi, method, order=n, average=False)
    if method in MC_METHODS:
        return albedo_by(brdf, mu, phi, method, samples=n, seed=seed, average=False)
    return albedo_by(brdf, mu, phi, "table", average=False)


def _point(res: dict, E_ref: np.ndarray, ref_err: np.ndarray) -> dict | None:
    E, err = np.asarray(res["E"], dtype=float), np.asarray(res["E_error"], dtype=float)
    if not (np.all(np.isfinite(E)) and np.all(np.isfinite(err))):
        return None          # a quadrature the time budget cut before its first comparison
    dev = np.abs(E - E_ref)
    return {"evaluations": int(res["evaluations"]), "seconds": float(res["seconds"]),
            "error": float(np.max(dev)), "error_rms": float(np.sqrt(np.mean(dev * dev))),
            "E_error": float(np.max(err)),
            "within_reported": float(np.mean(dev <= err + ref_err))}


def _table_point(brdf, mu, phi, E_ref, ref_err) -> tuple[dict | None, dict]:
    """The lookup, timed after a first call that builds the tables if they are not
    cached yet (whose cost is reported apart, with the table's own error bound)."""
    misses = tables.table_for_key.cache_info().misses
    first = _run(brdf, mu, phi, "table", 0, 0)
    built_now = tables.table_for_key.cache_info().misses > misses
    lookup = _run(brdf, mu, phi, "table", 0, 0)
    info = dict(first.get("table") or {})
    info.update(built_in_this_request=built_now,
                first_call_seconds=float(first["seconds"]))
    return _point(lookup, E_ref, ref_err), info


def tradeoff(brdf: BRDF, key, mu=DEFAULT_MU, phi: float = 0.0, methods=None,
             max_budget: int = DEFAULT_MAX_BUDGET, seed: int = 0) -> dict:
    """Error against cost of every method in ``methods`` (default: all that apply), at
    every budget up to ``max_budget``, for E at cosines ``mu``, azimuth ``phi``
    (radians). ``key``: hashable model values, the reference's cache key.

    Per point (arrays of equal length, method by method, budgets ascending): method,
    method_index, budget, evaluations, seconds, error, error_rms, E_error,
    within_reported; and the reference, the methods that do not apply with the reason,
    the table's build cost, and a note when the time budget stopped a method.
    ``cached``: the result (timings included) is that of an earlier identical call;
    complete results are kept (RESULT_CACHE_ENTRIES), cut ones never.
    """
    asked = tuple(dict.fromkeys(methods)) if methods else METHODS
    mu_key = tuple(float(m) for m in np.atleast_1d(mu))
    data, cached = _from_cache(_tradeoff_cached, Keyed(brdf, key), mu_key, float(phi), asked,
                               int(max_budget), int(seed))
    data["cached"] = cached
    return data


@complete_only(RESULT_CACHE_ENTRIES, complete=lambda data: data["complete"])
def _tradeoff_cached(model: Keyed, mu: tuple, phi: float, methods: tuple, max_budget: int,
                     seed: int) -> dict:
    _mark_computed()
    return freeze(_measure(model.value, model.key, np.asarray(mu), phi, methods, max_budget, seed))


def _measure(brdf: BRDF, key, mu: np.ndarray, phi: float, asked: tuple, max_budget: int,
             seed: int) -> dict:
    t0 = time.perf_counter()
    reasons = not_applicable(brdf)
    skipped = [{"method": m, "reason": reasons[m]} for m in asked if m in reasons]
    run = [m for m in asked if m not in reasons]
    b = budget.current()
    notes: list[str] = []
    seen = len(b.notes) if b is not None else 0

    def label(what: str) -> None:
        """Notes the budget gained since the last call, said of ``what``."""
        nonlocal seen
        if b is not None:
            notes.extend(f"{what}: {n}" for n in b.notes[seen:])
            seen = len(b.notes)

    ref, cached = reference(brdf, key, mu, phi)
    label(f"reference (quadrature to {REFERENCE_TOL:g})")
    E_ref, ref_err = ref["E"], ref["E_error"]
    plan = {m: budgets(m, max_budget) for m in run}
    points: dict[str, list[dict]] = {m: [] for m in run}
    stopped: dict[str, str] = {}
    table_info = None
    for level in range(max((len(p) for p in plan.values()), default=0)):
        for m in run:
            if m in stopped or level >= len(plan[m]):
                continue
            n = plan[m][level]
            # Each method's smallest budget (milliseconds) always runs, within the
            # request's grace (cost.GRACE_SECONDS): an answer has a point of every
            # method even when the reference took the whole budget on a busy machine.
            if m == "table":
                predicted = TABLE_RESERVE_SECONDS
            elif level == 0:
                predicted = None
            else:
                predicted = points[m][-1]["seconds"] * _cost_growth(m, plan[m][level - 1], n)
            if b is not None and predicted is not None and not b.affords(predicted):
                stopped[m] = (f"{m} stopped before budget {n} (predicted {predicted:.2g} s) "
                              "to end within the time budget")
                continue
            try:
                if m == "table":
                    p, table_info = _table_point(brdf, mu, phi, E_ref, ref_err)
                else:
                    p = _point(_run(brdf, mu, phi, m, n, seed), E_ref, ref_err)
            except ParameterError as exc:     # a rule not_applicable does not know yet
                skipped.append({"method": m, "reason": str(exc)})
                stopped[m] = ""
                continue
            finally:
                label("table (build)" if m == "table" else f"{m} at budget {n}")
            if p is None:
                stopped[m] = f"{m} cut by the time budget at budget {n}"
                continue
            points[m].append({"method": m, "budget": n, **p})
    notes += [s for s in stopped.values() if s]
    done = [m for m in run if points[m]]
    rows = [p for m in done for p in points[m]]
    out = {
        "method": [p["method"] for p in rows],
        "method_index": np.array([done.index(p["method"]) for p in rows], dtype=int),
        **{k: np.array([p[k] for p in rows], dtype=int) for k in ("budget", "evaluations")},
        **{k: np.array([p[k] for p in rows], dtype=float)
           for k in ("seconds", "error", "error_rms", "E_error", "within_reported")},
        "quantity": "albedo",
        "methods": done,
        "method_legend": "; ".join(f"{i} {m}" for i, m in enumerate(done)),
        "not_applicable": skipped,
        "mu_count": int(mu.size),
        "max_budget": int(max_budget),
        "seed": int(seed),
        "reference": ref,
        "reference_error": ref["error"],
        "reference_evaluations": ref["evaluations"],
        "reference_seconds": ref["seconds"],
        "reference_cached": cached,
        "timing": TIMING,
    }
    if table_info is not None:
        out["table"] = table_info
        out["table_build_seconds"] = table_info.get("build_seconds")
        out["table_build_evaluations"] = table_info.get("build_evaluations")
    out["complete"] = not notes
    if notes:
        out["note"] = "; ".join(notes)
    out["seconds_total"] = time.perf_counter() - t0
    return out
