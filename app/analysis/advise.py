"""Model only what the scene requires: for each cheaper choice of the model, its largest
albedo error over the scene's range of α and θ and its measured cost; the cheapest
combination within a tolerance. Metric, grid, bound and cost: docs/advise.md.

``recommendation`` is a model as every endpoint takes it (make_spec(**it) works), the
cheapest within ``tol``, or the current model (max_error 0, relative_cost 1). Row 0 of
the arrays ``max_errors``, ``relative_costs``, ``within_tol`` is the current model; row
k is ``alternatives[k - 1]``.

References: Kulla & Conty 2017 (E(μ) as the measure of lost energy; the E(μ, α)
tables); Karis 2013 and Walter et al. 2007 (the approximate Λ); Heitz 2014 (G2 forms).
"""
from __future__ import annotations

import itertools
import time

import numpy as np

from ..errors import Busy, ParameterError
from ..integrate import budget
from ..integrate.sampling import SAMPLERS
from ..model import OPTIONS, ModelSpec, choice_params, make_spec
from ..physics.fresnel import FRESNELS
from ..physics.g2 import G2_FORMS
from ..physics.masking import MASKINGS
from ..physics.masking import REFERENCE as MASKING_REFERENCE
from .albedo_grid import (GRID_SAFETY, N_MU, QUAD_TOL, Grid, Scene, _affords, _cut, albedo_grid,
                          is_anisotropic, model_error)
from .cost import CHEAPER_BELOW, COST_PAIRS, COST_SECONDS_FLOOR, seconds_per_batch
from .pointwise import F_FLOOR, N_PHI, N_THETA, POINTWISE_SAFETY, f_grid, pointwise_error

#: What a cheaper model is rated by: its albedo E(μ) (energy per direction) or f itself
#: at every pair of directions (what a point light shows; pointwise.py).
METRICS = ("albedo", "pointwise")

#: Combinations of the acceptable single choices whose error is evaluated, at most.
MAX_COMBINATIONS = 12
#: Monte Carlo: samples per μ tried, the sampler preference, and the bound in σ (one
#: standard error is what montecarlo.py reports; 3σ is a bound at 99.7 % per point).
MC_SAMPLES = (256, 1024, 4096)
MC_SAMPLERS = ("vndf", "ndf", "cosine")
MC_SIGMAS = 3.0
MC_SEED = 0
#: Time that must be left to start a step that may build an E(μ, α) table (a Kulla-Conty
#: model with another masking or G2, or the table method), per table. A build is not
#: bounded by the budget (its quadratures shorten, it goes on: a Beckmann Schlick pair
#: took 32 s under a 10 s budget on a loaded 2-core machine) and takes 1.7 s for GGX (tables.py,
#: 56², idle), 9 s for Beckmann and the slow lobes (measured, idle). With the default
#: BRDF_MAX_SECONDS = 10 a request never starts one and says so in its note; the CLI and
#: Python (no budget) run every step, and a raised BRDF_MAX_SECONDS lets requests do it.
TABLE_RESERVE_SECONDS = 10.0
#: Complete results kept (each a few kB).
RESULT_CACHE_ENTRIES = 64


#: The simplest G2, suggested for every exact correlated form: G1(l)·G1(v).
SIMPLEST_G2 = "separable"


def fresnel_params(values: dict) -> dict:
    return {p.name: values[p.name] for p in choice_params("fresnel", values["fresnel"])}


# --------------------------------------------------------------------- the choices ---

def single_changes(values: dict) -> list[dict]:
    """Option changes that make the model simpler, each {option: choice, ...}, those that
    apply to its NDF (make_spec refuses the rest later)."""
    ndf, out = values["ndf"], []

    def applies(entry) -> bool:
        return entry.applies_to is None or ndf in entry.applies_to

    if MASKINGS[values["masking"]].approximates is None:      # Smith's own Λ, or its integral
        out += [{"masking": name} for name, m in MASKINGS.items()
                if name not in (values["masking"], MASKING_REFERENCE) and applies(m)]
    g2 = G2_FORMS[values["g2"]]
    if g2.approximates is None and g2.name != SIMPLEST_G2:
        out.append({"g2": SIMPLEST_G2})
    out += [{"g2": name} for name, form in G2_FORMS.items()     # Hammon's, of the height-
            if form.approximates == g2.name and applies(form)]  # correlated form
    if FRESNELS[values["fresnel"]].approximates is None and \
            FRESNELS[values["fresnel"]](**fresnel_params(values)).schlick_basis() is None:
        # an exact form the tables cannot hold: its approximations, with the same F₀
        out += [{"fresnel": name} for name, cls in FRESNELS.items() if cls.approximates]
    if values["multiscatter"] == "kulla_conty":
        out.append({"multiscatter": "none"})
    return out


def label(changes: dict) -> str:
    return ", ".join(f"{k}={v}" for k, v in changes.items())


def recommend_dict(given: dict, values: dict, changes: dict, f0: float) -> dict:
    """The model with ``changes``, as the endpoints take it: what the request gave, every
    option named, parameters that no longer apply removed; Schlick takes F₀ = F(cos 0) of
    the exact form it replaces (how quantities.fresnel_curve pairs them, reversed)."""
    out = {k: v for k, v in given.items()}
    out.update({option: values[option] for option in OPTIONS})
    out.update(changes)
    if "fresnel" in changes and changes["fresnel"] != values["fresnel"]:
        for p in choice_params("fresnel", values["fresnel"]):
            out.pop(p.name, None)
        out["f0"] = f0
    if "g2" in changes and not G2_FORMS[out["g2"]].needs_phi:
        out.pop("lambda_phi", None)
    return out


# ----------------------------------------------------------------------- the advice ---

def _measure(model: dict, scene: Scene, metric: str, name: str):
    """The model's grid under ``metric``: E at the albedo nodes, or f at the pointwise ones."""
    if metric == "pointwise":
        return f_grid(model, scene, name=name)
    return albedo_grid(model, scene, name=name)


def _compare(ref, alt, scene: Scene, metric: str) -> dict | None:
    return pointwise_error(ref, alt, scene) if metric == "pointwise" else model_error(ref, alt, scene)


def _entry(kind: str, changes: dict, model: dict, err: dict | None, cost: float | None,
           tol: float, grid: Grid | None) -> dict:
    """One row: ``max_error`` is the bound the choice is judged by, ``max_difference``
    (= ``node_max``) the largest difference measured at the nodes."""
    out = {"kind": kind, "label": label(changes), "changes": changes, "model": model,
           "max_error": None if err is None else err["max_error"],
           "max_difference": None if err is None else err["node_max"],
           "relative_cost": cost,
           "within_tol": err is not None and err["max_error"] <= tol,
           "cheaper": cost is not None and cost < CHEAPER_BELOW}
    if err is not None:
        out.update({k: err[k] for k in ("node_max", "quadrature_error", "worst_alpha",
                                        "worst_theta_deg", "worst_at") if k in err})
    if grid is not None:
        out.update(evaluations=grid.evaluations, seconds=grid.seconds)
    return out


def _new_tables(current: dict, model: dict) -> int:
    """Tables a Kulla-Conty ``model`` may build that ``current`` did not need: one when its
    lobe (masking, G2, λ(φ)) differs (compensation tabulates E of the lobe at F = 1)."""
    if model.get("multiscatter") != "kulla_conty":
        return 0
    lobe = ("masking", "g2", "lambda_phi")
    return int(any(model.get(k) != current.get(k) for k in lobe)
               or current.get("multiscatter") != "kulla_conty")


def advise(given: dict, tol: float, scene: Scene, albedo_methods: bool = False,
           spec: ModelSpec | None = None, metric: str = "albedo") -> dict:
    """The advice for the model ``given`` (its parameters as the request gave them;
    ``spec``: make_spec(**given) if the caller has it — with Kulla-Conty, building a
    model builds its table unless cached) under ``metric`` (METRICS)."""
    if metric not in METRICS:
        raise ParameterError("metric", f"metric must be one of {', '.join(METRICS)}; got {metric!r}")
    t0 = time.perf_counter()
    spec = spec or make_spec(**given)
    values = spec.values
    if is_anisotropic(values):
        raise ParameterError("alpha_y", "advise is for isotropic models: the range replaces α")
    fresnel = FRESNELS[values["fresnel"]](**fresnel_params(values))
    f0 = float(fresnel.F(np.array(1.0)))
    current = recommend_dict(given, values, {}, f0)
    b = budget.current()
    if b is not None and b.notes:
        # building the model itself (its Kulla-Conty table) used the time: every further
        # model built here would build it again (a build cut short is not cached)
        b.cut("advise: not started: setting up the model used the time budget")
        ref_grid = Grid([], [], 0, 0.0, False)
    else:
        ref_grid = _measure(given, scene, metric, "the current model")
    base_cost = seconds_per_batch(current) if ref_grid.complete else None
    grids: dict[str, Grid] = {}
    entries: list[dict] = []
    if ref_grid.complete:
        entries = _singles(given, values, f0, ref_grid, scene, tol, base_cost, grids, metric)
        entries += _combinations(given, values, f0, entries, ref_grid, scene, tol, base_cost,
                                 grids, metric)
    choices = [e for e in entries if e["within_tol"] and e["cheaper"]]
    best = min(choices, key=lambda e: (e["relative_cost"], e["max_error"]), default=None)
    rec = {"recommendation": best["model"] if best else current,
           "changes": best["changes"] if best else {},
           "max_error": best["max_error"] if best else 0.0,
           "max_difference": best["max_difference"] if best else 0.0,
           "relative_cost": best["relative_cost"] if best else 1.0}
    evaluations = ref_grid.evaluations
    if albedo_methods and ref_grid.complete:
        quad = grids[label(rec["changes"])] if best else ref_grid
        if metric != "albedo":          # the methods are rated on E, whatever rated the model
            quad = albedo_grid(rec["recommendation"], scene, name="the recommended model")
        left = tol - rec["max_error"] if metric == "albedo" else tol
        methods = _albedo_methods(rec["recommendation"], quad, scene, left)
        entries += methods["entries"]
        rec["albedo_method"] = methods["choice"]
        evaluations += methods["evaluations"]
    evaluations += sum(e.get("evaluations", 0) for e in entries)
    b = budget.current()
    complete = not (b and b.notes)
    rows = [{"label": "current model", "max_error": 0.0, "max_difference": 0.0,
             "relative_cost": 1.0, "within_tol": True}] + entries
    out = {**rec, "alternatives": entries, "tol": tol, "current": current,
           "range": {"alpha_min": scene.alpha_min, "alpha_max": scene.alpha_max,
                     "theta_max_deg": scene.theta_max_deg},
           "metric": metric, "metric_text": _metric_text(metric),
           **({"f_floor": F_FLOOR} if metric == "pointwise" else {}),
           "grid": _grid_text(metric, scene),
           "row_labels": "; ".join(r["label"] for r in rows),
           "label": [r["label"] for r in rows],
           "max_errors": [r["max_error"] for r in rows],
           "max_differences": [r.get("max_difference") for r in rows],
           "relative_costs": [r["relative_cost"] for r in rows],
           "within_tol": [bool(r["within_tol"]) for r in rows],
           "cost": {"pairs": COST_PAIRS, "current_seconds": base_cost,
                    "clock": "thread CPU time, least of repeated runs, one thread"},
           "evaluations": evaluations, "seconds": time.perf_counter() - t0,
           "complete": complete}
    if not complete:
        out["note"] = "; ".join(b.notes) + " (setting BRDF_MAX_SECONDS)"
    return out


def _metric_text(metric: str) -> str:
    if metric == "pointwise":
        return (f"largest |f_alt − f_ref| / max(f_ref, {F_FLOOR:.4g} sr⁻¹) over the range of α and "
                f"both angles (the floor: 1 % of a white Lambertian f, for f near zero): "
                f"max_difference at the nodes, max_error = {POINTWISE_SAFETY:g} × that")
    return ("largest |E_alt(μ) − E_ref(μ)| (directional albedo, energy per direction) over the "
            "range: max_difference at the nodes; max_error, the bound, = min(1, "
            f"{GRID_SAFETY:g} × (max_difference + the quadrature error bounds there) + those bounds)")


def _grid_text(metric: str, scene: Scene) -> dict:
    if metric == "pointwise":
        return {"alpha": len(scene.alphas()), "theta_l": N_THETA, "theta_v": N_THETA, "phi": N_PHI}
    return {"alpha": len(scene.alphas()), "mu_per_alpha": N_MU, "quadrature_tol": QUAD_TOL}


def _singles(given, values, f0, ref_grid, scene, tol, base_cost, grids: dict,
             metric: str = "albedo") -> list[dict]:
    """Every single simpler choice: its error over the range and its relative cost."""
    entries, last = [], ref_grid.seconds
    for changes in single_changes(values):
        model = recommend_dict(given, values, changes, f0)
        tables = _new_tables(values, model)
        # checked before make_spec: a model with Kulla-Conty builds its table there
        if not _affords(last + TABLE_RESERVE_SECONDS * tables):
            _cut(f"advise: {label(changes)} not evaluated (no time left"
                 + (" for a Kulla-Conty table build)" if tables else ")"))
            entries.append(_entry("single", changes, model, None, None, tol, None))
            continue
        try:
            make_spec(**model)
        except ParameterError:
            continue                      # this choice does not combine with the model
        grid = _measure(model, scene, metric, label(changes))
        last, grids[label(changes)] = max(last, grid.seconds), grid
        cost = seconds_per_batch(model) / base_cost if grid.complete else None
        entries.append(_entry("single", changes, model, _compare(ref_grid, grid, scene, metric),
                              cost, tol, grid))
    return entries


def _combinations(given, values, f0, entries, ref_grid, scene, tol, base_cost,
                  grids: dict, metric: str = "albedo") -> list[dict]:
    """Products of the acceptable single choices (at most one per option), two or more
    changes at once, tried cheapest first (their error measured directly: errors of
    separate choices do not add); stops at the first within tol, which is the cheapest."""
    ok = [e for e in entries if e["within_tol"]]
    by_option: dict[str, list[dict]] = {}
    for e in ok:
        for option, choice in e["changes"].items():
            by_option.setdefault(option, []).append({option: choice})
    if len(by_option) < 2:
        return []
    last = max([ref_grid.seconds] + [g.seconds for g in grids.values()])
    cheapest_single = min((e["relative_cost"] for e in ok if e["cheaper"]), default=CHEAPER_BELOW)
    candidates = []
    for combo in itertools.product(*([{}] + opts for opts in by_option.values())):
        changes = {k: v for part in combo for k, v in part.items()}
        if len(changes) < 2:
            continue
        model = recommend_dict(given, values, changes, f0)
        if not _affords(last + TABLE_RESERVE_SECONDS * _new_tables(values, model)):
            _cut(f"advise: combination {label(changes)} not tried (no time left)")
            continue
        try:
            make_spec(**model)
        except ParameterError:
            continue
        cost = seconds_per_batch(model) / base_cost
        if cost < cheapest_single:
            candidates.append((cost, changes, model))
    out = []
    for cost, changes, model in sorted(candidates, key=lambda c: c[0])[:MAX_COMBINATIONS]:
        if not _affords(last):
            _cut(f"advise: combination {label(changes)} not evaluated (no time left)")
            out.append(_entry("combination", changes, model, None, cost, tol, None))
            continue
        grid = _measure(model, scene, metric, label(changes))
        last, grids[label(changes)] = max(last, grid.seconds), grid
        e = _entry("combination", changes, model, _compare(ref_grid, grid, scene, metric), cost,
                   tol, grid)
        out.append(e)
        if e["within_tol"]:
            break
    return out


# ------------------------------------------------------------------ albedo methods ---

def _albedo_methods(model: dict, quad: Grid, scene: Scene, tol_left: float) -> dict:
    """Table and Monte Carlo for E of ``model``, rated against its quadrature on the same
    nodes; the choice is the cheapest whose error fits in what the model's error leaves
    of tol (quadrature if none does)."""
    spec = make_spec(**model)
    quad_err = max(float(np.max(e)) for e in quad.E_error)
    # time the quadrature again: the grid above may include numba's first compilation
    timed = albedo_grid(model, scene, cache=False) if _affords(quad.seconds) else quad
    if not timed.complete:
        timed = quad
    entries = []
    # The table's first build takes seconds (2-9 s a table measured): a build the budget
    # cuts is returned with its larger, honest error and not cached (tables.py).
    methods: list[tuple[str, dict]] = []
    n_tables = len(spec.brdf().fresnel.schlick_basis() or ())
    if _affords(TABLE_RESERVE_SECONDS * n_tables):
        methods.append(("table", {}))
    else:
        _cut("advise: albedo by table not rated (its tables may need building, up to "
             f"~{TABLE_RESERVE_SECONDS:g} s each, more than the time left)")
    sampler = next((f"mc_{n}" for n in MC_SAMPLERS if SAMPLERS[n].supports(spec.brdf())), None)
    if sampler is not None:
        methods += [(sampler, {"samples": n, "seed": MC_SEED}) for n in MC_SAMPLES]
    for method, kw in methods:
        if not _affords(timed.seconds):
            _cut(f"advise: albedo by {method} not rated (no time left)")
            break
        try:
            grid = albedo_grid(model, scene, method, cache=False, **kw)
        except ParameterError:
            continue                                     # the table does not apply
        except Busy as exc:                              # its table is still being built
            _cut(f"advise: albedo by {method} not rated now ({exc.message})")
            continue
        build = 0.0
        if method == "table" and grid.complete:          # its cost: the lookups, not the build
            first, grid = grid, albedo_grid(model, scene, method, cache=False, **kw)
            build = max(first.seconds - grid.seconds, 0.0)
        if not grid.complete:
            continue                                     # cut: no bound over the range
        dev = max(float(np.max(np.abs(a - r))) for a, r in zip(grid.E, quad.E))
        own = max(float(np.max(e)) for e in grid.E_error)
        # table: its own global bound; MC: MC_SIGMAS standard errors (σ is smooth in μ)
        claimed = own if method == "table" else MC_SIGMAS * GRID_SAFETY * own
        err = max(claimed, GRID_SAFETY * (dev + quad_err) + quad_err)
        changes = {"albedo_method": method, **({"samples": kw["samples"]} if kw else {})}
        entries.append({"kind": "albedo_method", "label": label(changes), "changes": changes,
                        "model": model, "max_error": err, "node_max": dev,
                        "relative_cost": grid.seconds / max(timed.seconds, COST_SECONDS_FLOOR),
                        "within_tol": err <= tol_left,
                        "cheaper": grid.seconds < CHEAPER_BELOW * timed.seconds,
                        "evaluations": grid.evaluations, "seconds": grid.seconds,
                        **({"build_seconds": build} if method == "table" else {})})
    fits = [e for e in entries if e["within_tol"] and e["cheaper"]]
    best = min(fits, key=lambda e: e["relative_cost"], default=None)
    choice = {"method": "quadrature", "max_error": quad_err, "relative_cost": 1.0,
              "quadrature_seconds": timed.seconds}
    if best is not None:
        choice = {"method": best["changes"]["albedo_method"], "samples": best["changes"].get("samples"),
                  "max_error": best["max_error"], "relative_cost": best["relative_cost"],
                  "quadrature_seconds": timed.seconds}
    return {"entries": entries, "choice": choice,
            "evaluations": timed.evaluations if timed is not quad else 0}
