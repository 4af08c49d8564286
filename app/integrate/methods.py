"""The directional albedo by a chosen ``method``, with its error and cost:

* ``quadrature`` — the deterministic reference (albedo.py); ``order`` fixes the Gauss
  order (one comparison N vs 2N), otherwise it refines to ``tol``. E_error is a bound.
* ``mc_uniform``, ``mc_cosine``, ``mc_ndf``, ``mc_vndf`` — Monte Carlo (montecarlo.py)
  with ``samples`` directions per μ; E_error is one standard error.
* ``table`` — the interpolated E(μ, α) tables (tables/): F = 1 or generalised Schlick,
  isotropic; E_error is the table's measured error bound; no integrand evaluations at
  lookup (the build's are reported under ``table``).
* ``auto`` — the cheapest whose error bound meets ``tol``: the table if it applies and its
  bound is ≤ tol, else the quadrature at ``tol``; never Monte Carlo (one standard error is
  not a bound). The response names the method used.

With Kulla-Conty the method gives E_single and the multiple-scattering albedo F_ms (1 − Ê(μ))
is added exactly (compensation.py, docs/kulla_conty.md §3); E_single, F_avg, Ē are reported."""
from __future__ import annotations

import time

import numpy as np

from ..errors import Busy, ParameterError
from ..physics.brdf import BRDF, CompensatedBRDF
from .albedo import DEFAULT_TOL, albedo, albedo_average
from .montecarlo import SAMPLERS, albedo_mc
from .tables import TableTooSlow, table_for, tabulated_albedo

MC_METHODS = {f"mc_{name}": name for name in SAMPLERS}
METHODS = ("quadrature", *MC_METHODS, "table", "auto")
DEFAULT_SAMPLES = 1024
#: Most Monte Carlo directions per μ one request may ask for (the total over all μ is
#: bounded by the setting BRDF_MAX_MC_EVALUATIONS).
MC_SAMPLES_MAX = 2 ** 20


def _table(brdf: BRDF, mu) -> dict:
    t0 = time.perf_counter()
    try:
        E, error, tables = tabulated_albedo(brdf, mu)
    except ParameterError:          # a limit names its own parameter
        raise
    except ValueError as exc:
        raise ParameterError("method", str(exc)) from exc
    return {"E": E, "E_error": np.full(E.shape, error), "evaluations": 0,
            "seconds": time.perf_counter() - t0,
            "table": {"size": tables[0].size if tables else None, "error": error,
                      "build_seconds": sum(t.build_seconds for t in tables),
                      "build_evaluations": sum(t.build_evaluations for t in tables)}}


def single_albedo(brdf: BRDF, mu, phi: float, method: str, tol: float = DEFAULT_TOL,
                  order: int | None = None, samples: int = DEFAULT_SAMPLES, seed: int = 0) -> dict:
    """E(μ) of a single-scattering BRDF by ``method`` (not ``auto``)."""
    mu = np.atleast_1d(np.asarray(mu, dtype=float))
    if method == "quadrature":
        res = albedo(brdf, mu, phi, tol, order)
        return {"E": res.E, "E_error": res.E_error, "evaluations": res.evaluations,
                "seconds": res.seconds, "order": res.order}
    if method in MC_METHODS:
        try:
            res = albedo_mc(brdf, mu, phi, MC_METHODS[method], samples, seed)
        except ParameterError:      # a limit (TooLarge) names its own parameter
            raise
        except ValueError as exc:
            raise ParameterError("method", f"method={method}: {exc}") from exc
        return {"E": res.E, "E_error": res.E_error, "evaluations": res.evaluations,
                "seconds": res.seconds, "samples": res.samples, "seed": res.seed}
    if method == "table":
        if not brdf.ndf.isotropic:
            raise ParameterError("method", "method=table is for isotropic roughness only "
                                        "(alpha_y = alpha)")
        return _table(brdf, mu)
    raise ParameterError("method", f"method must be one of {', '.join(METHODS)}; got {method!r}")


def choose(brdf: BRDF, tol: float) -> tuple[str, str]:
    """``auto``: the table when it applies and meets tol, else the quadrature; and why
    (the response says it: a model whose table is refused or too loose for tol looks
    like any other, and a user asks why auto took the slow method)."""
    if not brdf.ndf.isotropic:
        return "quadrature", "no table: tables are for isotropic roughness only"
    try:
        bound = tabulated_albedo(brdf, [0.5], ready_only=True)[1]
    except TableTooSlow as exc:
        return "quadrature", f"the table was not built: {exc}"
    except Busy as exc:
        return "quadrature", f"no table yet: {exc.message}"
    except ValueError as exc:
        return "quadrature", f"no table: {exc}"
    if bound <= tol:
        return "table", f"the table's bound {bound:.2g} ≤ tol {tol:g}"
    return "quadrature", f"the table's bound {bound:.2g} > tol {tol:g}"


def albedo_by(brdf: BRDF, mu, phi: float = 0.0, method: str = "quadrature",
              tol: float = DEFAULT_TOL, order: int | None = None,
              samples: int = DEFAULT_SAMPLES, seed: int = 0, average: bool = True) -> dict:
    """E(μ) of the model as configured, by ``method``; with ``average`` also E_avg.

    Keys: mu, E, E_error, evaluations, seconds, method (the one used), requested_method
    (and with ``auto`` auto_reason, why it chose that method);
    with compensation E_single, E_single_error, F_avg, E_avg_single (Kulla-Conty's Ē) and
    F_ms; ``E_avg``/``E_avg_error`` when ``average``.
    """
    t0 = time.perf_counter()
    mu = np.atleast_1d(np.asarray(mu, dtype=float))
    requested = method
    single = brdf.single() if isinstance(brdf, CompensatedBRDF) else brdf
    reason = None
    if method == "auto":
        method, reason = choose(single, tol)
    out = single_albedo(single, mu, phi, method, tol, order, samples, seed)
    out.update(mu=mu, method=method, requested_method=requested)
    if reason is not None:
        out["auto_reason"] = reason
    if average:
        if method == "table":
            avg = _table_average(single)
            out.update(E_avg=avg[0], E_avg_error=avg[1])
        else:
            # E_avg by the deterministic rule whatever the method: a number without
            # its own sampling noise, computed to the request's tol.
            E_avg, E_avg_error, evals = albedo_average(single, phi, tol)
            out.update(E_avg=E_avg, E_avg_error=E_avg_error)
            out["evaluations"] += evals
    kc = getattr(brdf, "multiscatter", None)
    if kc is not None:
        E_ms = kc.albedo(mu)
        out.update(E_single=out["E"], E_single_error=out["E_error"], E=out["E"] + E_ms,
                   F_avg=kc.F_avg, E_avg_single=kc.E_avg, F_ms=kc.F_ms,
                   compensation_error=kc.error)
        if average:
            out["E_single_avg"] = out["E_avg"]
            out["E_avg"] = out["E_avg"] + kc.albedo_average()
    out["seconds"] = time.perf_counter() - t0
    return out


def _table_average(brdf: BRDF) -> tuple[float, float]:
    """E_avg from the tables: Σ_lobes w Σ_basis c Ē_basis (Fresnel.schlick_basis) + E_d,avg
    (the diffuse term's, kd for Lambert)."""
    parts = brdf.fresnel.schlick_basis()
    total, error = brdf.diffuse_albedo_avg()
    for w, lobe in brdf.lobes():
        for c, basis in parts:
            if c:
                table = table_for(lobe, basis)
                total += w * c * table.E_avg(lobe.ndf.alpha_x)
                error += abs(w * c) * table.error
    return total, error
