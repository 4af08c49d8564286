"""Model only what the scene requires: for each cheaper choice, its largest error over the
roughness and angles a scene uses and its measured cost; the cheapest combination within
a tolerance (issue 4).

Reference and range
-------------------
The reference is the model as configured. The scene's range is α ∈ [α_min, α_max] (the
model's own α is replaced by each α of the range; a second lobe's α₂ is kept) and
θ ∈ [0, θ_max] for the view and the light. Anisotropic models are refused (the API
answers 422): one α per scene does not say how α_x and α_y would scale, the metric would
need a φ axis as well, and the table, Kulla-Conty and Hammon choices are isotropic only.

Metric
------
The absolute error of the directional albedo, |E_alt(μ) − E_ref(μ)| with
E(μ) = ∫ f(l, v) (n·l) dl (MATH.md), the largest over the range. E is energy per
direction, in [0, 1] for every model; it is finite where f·cos θ is not bounded (the
mirror peak at α → 0), so the same number rates every choice: an approximate Λ, a simpler
G2, Schlick's Fresnel, no multiple scattering, and the albedo methods (table, Monte
Carlo) in the same units. By reciprocity E(μ) is also the reflectance for light arriving
at θ (MATH.md), so θ ≤ θ_max covers the view and the light alike. It does not see an
error that moves energy within the lobe without changing its total.

Every E comes from the deterministic quadrature (app/integrate/methods.albedo_by, which
adds the exact Kulla-Conty term), at the nodes: N_ALPHA values of α, geometric in the
range, and for each N_MU cosines uniform in Smith's variable y = √a/(1 + √a),
a = μ/(α sinθ) (the axis of app/integrate/tables.py), from θ_max to the normal. Uniform
nodes in θ missed the grazing dip at μ ~ α of small α: the largest error of Karis's Λ over
α ∈ [0.01, 1], θ ≤ 90° was 0.033 on a 5 × 7 grid in θ and 0.185 on 41 × 91; in y the
5 × 8 grid found 0.192 (measured, see GRID_SAFETY).

The reported bound is GRID_SAFETY × (largest |ΔE| at the nodes + the quadrature error
bounds there) + that quadrature error again, so that it holds on a finer grid.

Cost
----
The relative cost of a model is the CPU time (``time.thread_time``: the calling thread,
so another process taking the core does not count) of evaluating f on COST_PAIRS fixed
direction pairs, the minimum of COST_REPEATS or more runs, over the same of the current model.
Below fast.PARALLEL_MIN pairs, so the compiled path (app/physics/fast.py) runs on one
thread like numpy does: it is the per-evaluation cost. Measured once per process and kind
of model (options, not continuous values) and kept (a bounded cache): a fixed cost model
measured lazily. The compiled path matters: with numba, GGX with the exact Smith Λ,
height-correlated G2 and Schlick takes 0.44 ms for 16 384 pairs; Karis's Λ, which the
compiled path does not cover, 4.0 ms — the "cheaper" formula is 9× dearer here. An
approximation is recommended only if it is measured cheaper (below CHEAPER_BELOW).

For the albedo methods (only when asked: a table's first build takes seconds) the cost is
the wall time of E on the same nodes by that method over the quadrature's.

Result
------
``recommendation`` is a model as every endpoint takes it (make_spec(**it) works), the
cheapest within ``tol``, or the current model (max_error 0, relative_cost 1). Row 0 of the
arrays ``max_errors``, ``relative_costs``, ``within_tol`` is the current model; row k is
``alternatives[k - 1]`` (the CSV export writes these columns).

References
----------
Kulla & Conty 2017 (E(μ) as the measure of lost energy; the E(μ, α) tables); Karis 2013
and Walter et al. 2007 (the approximate Λ); Heitz 2014 (G2 forms; Smith's a).
"""
from __future__ import annotations

import itertools
import time
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..integrate import budget
from ..integrate.cache import Keyed, complete_only, freeze
from ..integrate.albedo import DEFAULT_TOL
from ..errors import ParameterError
from ..integrate.methods import albedo_by
from ..integrate.tables import mu_from_y, y_from_mu
from ..integrate.sampling import SAMPLERS
from ..model import OPTIONS, ModelSpec, choice_params, make_spec
from ..physics.fresnel import FRESNELS
from ..physics.g2 import G2_FORMS
from ..physics.masking import MASKINGS

#: α nodes of the range (geometric) and μ nodes per α (uniform in Smith's y).
N_ALPHA = 6
N_MU = 9
#: Tolerance of each quadrature E (the /albedo default); its error bound enters max_error.
QUAD_TOL = DEFAULT_TOL
#: max_error = GRID_SAFETY × (node error); the largest |ΔE| grows between nodes. Measured
#: (/tmp bench, as in the tests: this 6 × 9 grid against 24 α × (36 nodes in y joined with
#: 36 uniform in θ), tol 1e-6; α ranges [1e-4, 1], [0.01, 1], [0.05, 0.5], [0.2, 0.3],
#: [0.1, 0.5], [0.02, 0.2] with θ_max 90°, 80°, 60°, 70°, 85°; GGX, Beckmann, dielectric,
#: conductor, direction-correlated and Kulla-Conty models; every single alternative, 67
#: cases): the largest growth was 1.48× (Walter's Λ on Beckmann, α ∈ [0.02, 0.2],
#: θ ≤ 85°, whose small error oscillates in a), then 1.13× (Schlick for gold), the rest
#: ≤ 1.04×. 2 covers it with margin.
GRID_SAFETY = 2.0
#: f evaluations timed per run (below fast.PARALLEL_MIN: one thread), at least this many
#: runs per model (the minimum is kept), and the CPU seconds after which a slow model
#: (smith_numeric: 0.3 s a run) stops repeating.
COST_PAIRS = 16_384
COST_REPEATS = 5
#: ... and runs go on until this much CPU time is spent (a 0.3 ms run alone was off by
#: up to 23 % under load; the minimum over ~60 runs, re-measured 12 times at load 2.7,
#: spread by −0.3 % .. +0.5 %).
COST_SECONDS_MIN = 0.02
COST_SECONDS_CAP = 0.25
COST_SEED = 0
#: α of the timed models (cost does not depend on it but through smith_numeric's orders).
COST_ALPHA = 0.3
#: Models timed and kept per process (a few floats each).
COST_CACHE_ENTRIES = 512
#: Smallest CPU time a timing reports: time.thread_time ticks in 1 µs or coarser, so a
#: run below a tick can read 0 and a relative cost would divide by it (here and for the
#: albedo methods' wall times); 1 ns is far below
#: any real run (the fastest measured, GGX compiled: 0.44 ms).
COST_SECONDS_FLOOR = 1e-9
#: A choice counts as cheaper when it costs below this fraction of the current model.
#: The cost of one model re-measured 12 times on this 2-core machine spread by −9 % .. +1 %
#: (GGX on the compiled path, 0.31 ms, load 4.4) and −3 % .. +7 % (Karis, 2.6 ms, load
#: 2.7): 0.85 keeps an equal-cost choice (separable G2 on the compiled path) from being
#: recommended on noise.
CHEAPER_BELOW = 0.85
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
#: took 32 s under a 10 s budget at load 4, measured) and takes 1.7 s for GGX (tables.py,
#: 56², idle), 9 s for Beckmann and the slow lobes (measured, idle). With the default
#: BRDF_MAX_SECONDS = 10 a request never starts one and says so in its note; the CLI and
#: Python (no budget) run every step, and a raised BRDF_MAX_SECONDS lets requests do it.
TABLE_RESERVE_SECONDS = 10.0
#: E grids kept (one per model and scene: 54 E and errors, ~1 kB).
GRID_CACHE_ENTRIES = 512
#: Complete results kept (each a few kB).
RESULT_CACHE_ENTRIES = 64

#: Continuous values that do not change what code runs (the cost key leaves them out).
_CONTINUOUS = {"alpha", "alpha_y", "roughness", "anisotropy", "aniso_map", "kd", "f0", "f90",
               "ior", "k", "alpha2", "lobe_mix"}
#: Options of the roughness form, replaced by alpha when α is set from the range.
_ROUGHNESS_FORM = ("roughness", "anisotropy", "aniso_map", "alpha_y")


@dataclass(frozen=True)
class Scene:
    alpha_min: float
    alpha_max: float
    theta_max_deg: float

    def alphas(self) -> np.ndarray:
        return np.unique(np.geomspace(self.alpha_min, self.alpha_max, N_ALPHA))

    def mu(self, alpha: float, n: int = N_MU) -> np.ndarray:
        """n cosines uniform in y from θ_max to the normal (fewer if they coincide)."""
        y0 = float(y_from_mu(np.cos(np.radians(self.theta_max_deg)), alpha))
        return np.unique(np.clip(mu_from_y(np.linspace(y0, 1.0, n), alpha), 0.0, 1.0))


def is_anisotropic(values: dict) -> bool:
    return values.get("alpha_y") is not None and values["alpha_y"] != values["alpha"]


def at_alpha(model: dict, alpha: float) -> dict:
    """The model with its α (in whichever form it was given) replaced by ``alpha``."""
    out = {k: v for k, v in model.items() if k not in _ROUGHNESS_FORM}
    out["alpha"] = float(alpha)
    return out


# --------------------------------------------------------------------- the choices ---

def single_changes(values: dict) -> list[dict]:
    """Option changes that make the model simpler, each {option: choice, ...}, those that
    apply to its NDF (make_spec refuses the rest later)."""
    ndf, out = values["ndf"], []
    if values["masking"] in ("smith", "smith_numeric"):
        for name, m in MASKINGS.items():
            if name in (values["masking"], "smith_numeric"):
                continue
            if m.applies_to is None or ndf in m.applies_to:
                out.append({"masking": name})
    g2 = values["g2"]
    if g2 in ("height_correlated", "direction_correlated", "height_direction_correlated"):
        out.append({"g2": "separable"})
    hammon = G2_FORMS["hammon"]
    if g2 == "height_correlated" and (hammon.applies_to is None or ndf in hammon.applies_to):
        out.append({"g2": "hammon"})            # approximates the height-correlated form
    if values["fresnel"] in ("dielectric", "conductor"):
        out.append({"fresnel": "schlick"})      # with the same F₀ (see recommend_dict)
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
    if changes.get("fresnel") == "schlick":
        for p in ("ior", "k"):
            out.pop(p, None)
        out["f0"] = f0
    if "g2" in changes and not G2_FORMS[out["g2"]].needs_phi:
        out.pop("lambda_phi", None)
    return out


# ------------------------------------------------------------------------ the errors ---

@dataclass
class Grid:
    """E and its quadrature error bound at the scene's nodes, one array per α."""
    E: list
    E_error: list
    evaluations: int
    seconds: float
    complete: bool


def albedo_grid(model: dict, scene: Scene, method: str = "quadrature", name: str = "",
                cache: bool = True, **kw) -> Grid:
    """E at every α of the range, or at the first ones only, when the time budget would
    not cover another row at the rate so far (``complete`` False: no bound over the range).

    With ``cache``, from a bounded cache of grids that were computed whole with no cut
    (keyed by the model's values, not by how the request spelled them): a request cut by
    the budget keeps the grids it finished, and the next one, or the same scene at
    another tol, starts from them. ``seconds`` is then that of the first computation."""
    if not cache:
        return _compute_grid(model, scene, method, name, kw)
    key = tuple(sorted(make_spec(**at_alpha(model, 1.0)).values.items()))
    return _grid_cached(Keyed((model, name), key), scene, method, tuple(sorted(kw.items())))


@complete_only(GRID_CACHE_ENTRIES, complete=lambda grid: grid.complete)
def _grid_cached(model: Keyed, scene: Scene, method: str, kw: tuple) -> Grid:
    """``model.value``: (the model dict, what a note calls it); keyed by its values."""
    values, name = model.value
    return _compute_grid(values, scene, method, name, dict(kw))


def _compute_grid(model: dict, scene: Scene, method: str, name: str, kw: dict) -> Grid:
    E, err, evals, t0 = [], [], 0, time.perf_counter()
    alphas = scene.alphas()
    for alpha in alphas:
        if E and not _affords((time.perf_counter() - t0) / len(E)):
            _cut(f"advise: E of {name or method} stopped at α = {alpha:.3g} (no time left)")
            break
        res = albedo_by(make_spec(**at_alpha(model, alpha)).brdf(), scene.mu(alpha),
                        method=method, tol=QUAD_TOL, average=False, **kw)
        E.append(np.asarray(res["E"], dtype=float))
        err.append(np.asarray(res["E_error"], dtype=float))
        evals += int(res["evaluations"])
    freeze(E + err)
    return Grid(E, err, evals, time.perf_counter() - t0, len(E) == len(alphas))


def model_error(ref: Grid, alt: Grid, scene: Scene) -> dict | None:
    """The bound on max |E_alt − E_ref| over the range (module docstring) and where the
    largest node difference is; None if either grid does not cover the range."""
    if not (ref.complete and alt.complete):
        return None
    worst, where, quad = -1.0, (0.0, 0.0), 0.0
    for alpha, a, r, ea, er in zip(scene.alphas(), alt.E, ref.E, alt.E_error, ref.E_error):
        d = np.abs(a - r)
        i = int(np.argmax(d))
        if d[i] > worst:
            worst, where = float(d[i]), (float(alpha), float(np.degrees(np.arccos(scene.mu(alpha)[i]))))
        quad = max(quad, float(np.max(ea + er)))
    return {"max_error": GRID_SAFETY * (worst + quad) + quad, "node_max": worst,
            "quadrature_error": quad, "worst_alpha": where[0], "worst_theta_deg": where[1]}


# -------------------------------------------------------------------------- the costs ---

def cost_key(model: dict) -> tuple:
    values = make_spec(**model).values
    kept = {k: v for k, v in values.items()
            if k not in _CONTINUOUS and isinstance(v, (str, int, float)) and k in _model_names()}
    kept["two_lobes"] = bool(values.get("lobe_mix")) and values.get("alpha2") is not None
    return tuple(sorted(kept.items()))


@lru_cache(maxsize=1)
def _model_names() -> frozenset:
    from ..model import COMMON_PARAMS, SUB_OPTIONS, choice_param_names
    return frozenset(OPTIONS) | frozenset(SUB_OPTIONS) | {p.name for p in COMMON_PARAMS} \
        | frozenset(choice_param_names())


@lru_cache(maxsize=1)
def _pairs() -> tuple[np.ndarray, np.ndarray]:
    """COST_PAIRS fixed (l, v), uniform over the upper hemisphere."""
    rng = np.random.default_rng(COST_SEED)
    u = rng.random((2, COST_PAIRS, 2))
    mu, phi = u[..., 0], 2.0 * np.pi * u[..., 1]
    s = np.sqrt(1.0 - mu * mu)
    w = np.stack([s * np.cos(phi), s * np.sin(phi), mu], axis=-1)
    freeze(w)
    return w[0], w[1]


@lru_cache(maxsize=COST_CACHE_ENTRIES)
def _seconds(kind: Keyed) -> float:
    """Least CPU seconds of f at the fixed pairs over the runs, for one kind of model
    (``kind.key``); the first model of that kind seen (``kind.value``) is the one timed
    (continuous values do not matter)."""
    brdf = make_spec(**at_alpha(kind.value, COST_ALPHA)).brdf()
    l, v = _pairs()
    brdf.evaluate(l, v)                          # warm-up: numba compiles on first use
    runs, spent = [], 0.0
    while not runs or (spent < COST_SECONDS_CAP
                       and (len(runs) < COST_REPEATS or spent < COST_SECONDS_MIN)):
        t0 = time.thread_time()
        brdf.evaluate(l, v)
        runs.append(time.thread_time() - t0)
        spent += runs[-1]
    return max(float(np.min(runs)), COST_SECONDS_FLOOR)


def seconds_per_batch(model: dict) -> float:
    return _seconds(Keyed(model, cost_key(model)))


# ----------------------------------------------------------------------- the advice ---

def _entry(kind: str, changes: dict, model: dict, err: dict | None, cost: float | None,
           tol: float, grid: Grid | None) -> dict:
    out = {"kind": kind, "label": label(changes), "changes": changes, "model": model,
           "max_error": None if err is None else err["max_error"],
           "relative_cost": cost,
           "within_tol": err is not None and err["max_error"] <= tol,
           "cheaper": cost is not None and cost < CHEAPER_BELOW}
    if err is not None:
        out.update({k: err[k] for k in ("node_max", "quadrature_error", "worst_alpha",
                                        "worst_theta_deg")})
    if grid is not None:
        out.update(evaluations=grid.evaluations, seconds=grid.seconds)
    return out


def _affords(seconds: float) -> bool:
    b = budget.current()
    return b is None or b.affords(seconds)


def _new_tables(current: dict, model: dict) -> int:
    """Tables a Kulla-Conty ``model`` may build that ``current`` did not need: one when its
    lobe (masking, G2, λ(φ)) differs (compensation tabulates E of the lobe at F = 1)."""
    if model.get("multiscatter") != "kulla_conty":
        return 0
    lobe = ("masking", "g2", "lambda_phi")
    return int(any(model.get(k) != current.get(k) for k in lobe)
               or current.get("multiscatter") != "kulla_conty")


def _cut(note: str) -> None:
    b = budget.current()
    if b is not None:
        b.cut(note)


def advise(given: dict, tol: float, scene: Scene, albedo_methods: bool = False,
           spec: ModelSpec | None = None) -> dict:
    """The advice for the model ``given`` (its parameters as the request gave them;
    ``spec``: make_spec(**given) if the caller has it — with Kulla-Conty, building a
    model builds its table unless cached)."""
    t0 = time.perf_counter()
    spec = spec or make_spec(**given)
    values = spec.values
    if is_anisotropic(values):
        raise ParameterError("alpha_y", "advise is for isotropic models: the range replaces α")
    fresnel = FRESNELS[values["fresnel"]](**{p.name: values[p.name]
                                             for p in choice_params("fresnel", values["fresnel"])})
    f0 = float(fresnel.F(np.array(1.0)))
    current = recommend_dict(given, values, {}, f0)
    b = budget.current()
    if b is not None and b.notes:
        # building the model itself (its Kulla-Conty table) used the time: every further
        # model built here would build it again (a build cut short is not cached)
        b.cut("advise: not started: setting up the model used the time budget")
        ref_grid = Grid([], [], 0, 0.0, False)
    else:
        ref_grid = albedo_grid(given, scene, name="the current model")
    base_cost = seconds_per_batch(current) if ref_grid.complete else None
    grids: dict[str, Grid] = {}
    entries: list[dict] = []
    if ref_grid.complete:
        entries = _singles(given, values, f0, ref_grid, scene, tol, base_cost, grids)
        entries += _combinations(given, values, f0, entries, ref_grid, scene, tol, base_cost,
                                 grids)
    choices = [e for e in entries if e["within_tol"] and e["cheaper"]]
    best = min(choices, key=lambda e: (e["relative_cost"], e["max_error"]), default=None)
    rec = {"recommendation": best["model"] if best else current,
           "changes": best["changes"] if best else {},
           "max_error": best["max_error"] if best else 0.0,
           "relative_cost": best["relative_cost"] if best else 1.0}
    evaluations = ref_grid.evaluations
    if albedo_methods and ref_grid.complete:
        quad = grids[label(rec["changes"])] if best else ref_grid
        methods = _albedo_methods(rec["recommendation"], quad, scene, tol - rec["max_error"])
        entries += methods["entries"]
        rec["albedo_method"] = methods["choice"]
        evaluations += methods["evaluations"]
    evaluations += sum(e.get("evaluations", 0) for e in entries)
    b = budget.current()
    complete = not (b and b.notes)
    rows = [{"label": "current model", "max_error": 0.0, "relative_cost": 1.0,
             "within_tol": True}] + entries
    out = {**rec, "alternatives": entries, "tol": tol, "current": current,
           "range": {"alpha_min": scene.alpha_min, "alpha_max": scene.alpha_max,
                     "theta_max_deg": scene.theta_max_deg},
           "metric": "largest |E_alt(μ) − E_ref(μ)| (directional albedo, energy per direction) "
                     f"over the range: {GRID_SAFETY:g} × (its largest value at the nodes + the "
                     "quadrature error bounds there) + those bounds",
           "grid": {"alpha": len(scene.alphas()), "mu_per_alpha": N_MU, "quadrature_tol": QUAD_TOL},
           "row_labels": "; ".join(r["label"] for r in rows),
           "max_errors": [r["max_error"] for r in rows],
           "relative_costs": [r["relative_cost"] for r in rows],
           "within_tol": [bool(r["within_tol"]) for r in rows],
           "cost": {"pairs": COST_PAIRS, "current_seconds": base_cost,
                    "clock": "thread CPU time, least of repeated runs, one thread"},
           "evaluations": evaluations, "seconds": time.perf_counter() - t0,
           "complete": complete}
    if not complete:
        out["note"] = "; ".join(b.notes) + " (setting BRDF_MAX_SECONDS)"
    return out


def _singles(given, values, f0, ref_grid, scene, tol, base_cost, grids: dict) -> list[dict]:
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
        grid = albedo_grid(model, scene, name=label(changes))
        last, grids[label(changes)] = max(last, grid.seconds), grid
        cost = seconds_per_batch(model) / base_cost if grid.complete else None
        entries.append(_entry("single", changes, model, model_error(ref_grid, grid, scene),
                              cost, tol, grid))
    return entries


def _combinations(given, values, f0, entries, ref_grid, scene, tol, base_cost,
                  grids: dict) -> list[dict]:
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
        grid = albedo_grid(model, scene, name=label(changes))
        last, grids[label(changes)] = max(last, grid.seconds), grid
        e = _entry("combination", changes, model, model_error(ref_grid, grid, scene), cost, tol, grid)
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
    n_tables = 1 if spec.values["fresnel"] == "none" else 2
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
