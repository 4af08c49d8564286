"""A fit request: data set + model family + free parameters → the fitted model, and
``fit_all``: the same fit for every NDF, ranked by residual."""
from __future__ import annotations

import time

import numpy as np

from ..datasets.dataset import BrdfData, TermData
from ..errors import ParameterError
from ..model import make_spec
from ..physics.ndf import NDFS
from .problem import FLOOR, free_params, make_problem
from .solve import solve

#: measured points a fit uses at most: a fixed-seed random subset of a larger data set
#: (a MERL table has ~1.1 M measured cells). 25 000 points fit GGX's three parameters in
#: well under a second on one core (BENCHMARKS.md, bench/fit.py)
MAX_POINTS = 25_000
#: relative RMS of (model − data)/data beyond which the fit says the model does not
#: describe the data: measured BRDFs carry a few per cent of noise (MERL: ~1–3 % per cell,
#: Matusik et al. 2003), so a model that is right leaves about that; 5 % is beyond it
MISFIT_RELATIVE_RMS = 0.05
FAVOURS = {"log": "every decade alike: the lobe's shape, tails as much as the peak",
           "relative": "like log, but an overshoot costs more: a model that stays under faint data",
           "cosine": "f·cos θ_l, the reflected radiance: the bright peak, grazing light little"}


def points(data, channel: str | None, max_points: int) -> tuple[dict, str]:
    """The problem's data arguments and a note of what was used."""
    if isinstance(data, TermData):
        term = channel or next(iter(data.terms))
        if term not in data.terms:
            raise ParameterError("channel", f"this data set holds {', '.join(data.terms)}; got "
                                            f"{channel!r}", loc="body")
        if data.axis != "theta_deg":
            raise ParameterError("data", "fits to E(μ) are not offered: fit the BRDF data it "
                                         "was integrated from", loc="body")
        return ({"target": data.terms[term], "term": term, "angle_deg": data.x},
                f"all {data.count} rows of {term}(θ)")
    l, v, f, note = data.points(channel, max_points)
    return {"target": f, "l": l, "v": v, "channel": channel}, note


def fit(data, model: dict, free: list[str], measure: str, channel: str | None,
        seconds: float, max_points: int = MAX_POINTS) -> dict:
    arguments, note = points(data, channel, max_points)
    problem = make_problem(model, free, measure, **arguments)
    usable = np.isfinite(problem.residual(problem.start))
    if not usable.all():   # the model diverges there (both directions grazing)
        problem = make_problem(model, free, measure, **_subset(arguments, usable))
        note += f"; {int((~usable).sum())} where the model diverges left out"
    out = solve(problem, seconds)
    spec = problem.spec(out["x"])
    fitted = spec.values
    names = [p.name for p in problem.free]
    stderr = out["stderr"]
    residual = _rms(out["r"])
    converged = out["converged"] and np.isfinite(residual)
    misfit = _misfit(problem, out["x"])
    return {
        "params": dict(zip(names, out["x"].tolist())),
        "stderr": None if stderr is None or not np.isfinite(stderr).all() else dict(zip(names, stderr.tolist())),
        "residual": residual if np.isfinite(residual) else None,
        "evaluations": out["evaluations"], "seconds": out["seconds"],
        "converged": bool(converged),
        "message": out["message"] if np.isfinite(residual) else (
            "the residual overflows float64 (the data's values are too large for this measure's "
            "squares): no fit"),
        "at_bound": out["at_bound"],
        "held_fixed": {n: fitted.get(n) for n in free_params(fitted) if n not in names
                       and fitted.get(n) is not None},
        "misfit": misfit,
        "model": as_model(fitted),
        "measure": {"name": measure, "favours": FAVOURS[measure],
                    "residual": "root mean square of the measure's residual over the points"},
        "points": {"count": int(out["r"].size), "note": note},
    }


def _rms(r: np.ndarray) -> float:
    """√mean(r²) without overflowing for |r| up to float64's largest (scaled by max |r|)."""
    scale = float(np.max(np.abs(r))) if r.size else 0.0
    if not np.isfinite(scale):
        return np.inf
    return scale * float(np.sqrt(np.mean((r / scale) ** 2))) if scale > 0 else 0.0


def _misfit(problem, x: np.ndarray) -> dict:
    """Whether the fitted model describes the data: the relative RMS of (model − data)/data
    over the points with data above the measures' floor, against MISFIT_RELATIVE_RMS."""
    model = problem.predict(x)
    ok = (problem.target > FLOOR) & np.isfinite(model)
    rms = _rms((model[ok] - problem.target[ok]) / problem.target[ok]) if ok.any() else None
    bad = rms is not None and (not np.isfinite(rms) or rms > MISFIT_RELATIVE_RMS)
    return {"relative_rms": rms if rms is not None and np.isfinite(rms) else None,
            "threshold": MISFIT_RELATIVE_RMS,
            "warning": (f"the model does not describe the data: relative RMS error "
                        f"{rms:.1%} > {MISFIT_RELATIVE_RMS:.0%}, beyond a measurement's noise; the "
                        "parameters (and their standard errors) describe the best of a wrong "
                        "model — free more parameters (see held_fixed) or try another NDF or Fresnel")
            if bad else None,
            "criterion": "relative RMS of (model − data)/data over the points with data > "
                         f"{FLOOR:.3g} sr⁻¹, warned above {MISFIT_RELATIVE_RMS:.0%}"}


#: values make_spec adds for display (Blinn-Phong's α_p): not parameters
DERIVED = {"alpha_p"}


def as_model(values: dict) -> dict:
    """A validated model's values as every endpoint takes them back (no display-only or
    absent values)."""
    return {k: v for k, v in values.items() if v is not None and k not in DERIVED}


def _subset(arguments: dict, keep: np.ndarray) -> dict:
    return {k: (v[keep] if isinstance(v, np.ndarray) else v) for k, v in arguments.items()}


def fit_all(data, model: dict, free: list[str], measure: str, channel: str | None,
            seconds: float, max_points: int = MAX_POINTS) -> dict:
    """The fit for every NDF of the registry with the rest of ``model`` (each NDF's own
    shape parameters at their defaults unless freed), ranked by residual; the time budget
    shared out between the NDFs still to fit."""
    if not isinstance(data, BrdfData):
        raise ParameterError("fit_all", "fit_all ranks NDFs against BRDF data", loc="body")
    ranking, skipped = [], []
    deadline = time.perf_counter() + seconds
    names = list(NDFS)
    for k, ndf in enumerate(names):
        trial = {key: v for key, v in model.items() if key not in _shape_names()} | {"ndf": ndf}
        try:
            make_spec(**trial)
        except ParameterError as exc:
            skipped.append({"ndf": ndf, "reason": exc.message})
            continue
        share = max(0.0, deadline - time.perf_counter()) / (len(names) - k)
        own_free = [n for n in free if n not in _shape_names() or n in _shape_names(ndf)]
        try:
            result = fit(data, trial, own_free, measure, channel, share, max_points)
        except ParameterError as exc:
            skipped.append({"ndf": ndf, "reason": exc.message})
            continue
        ranking.append({"ndf": ndf, **result})
    ranking.sort(key=lambda item: item["residual"])
    if not ranking:
        raise ParameterError("fit_all", "no NDF could be fitted: " + "; ".join(
            f"{s['ndf']}: {s['reason']}" for s in skipped), loc="body")
    return {**ranking[0], "ranking": ranking, "skipped": skipped}


def _shape_names(ndf: str | None = None) -> set[str]:
    from ..model import choice_params
    chosen = [ndf] if ndf else list(NDFS)
    return {p.name for name in chosen for p in choice_params("ndf", name)}
