"""The directional albedo E(μ) by a chosen method, with its error and cost."""
from __future__ import annotations

import numpy as np

from .. import quantities
from ..config import Settings
from ..errors import ParameterError
from ..figures.curves import albedo_figure
from ..integrate import budget
from ..integrate.albedo import max_evaluations
from ..integrate.cache import Keyed, complete_only, freeze, mark_cached
from ..model import ModelSpec
from . import schemas
from .view import View, limit

#: albedo results kept (each a few kB: E, E_error at ≤ BRDF_MAX_ALBEDO_POINTS μ values)
ALBEDO_CACHE_ENTRIES = 256


@complete_only(ALBEDO_CACHE_ENTRIES, complete=lambda data: data["complete"])
def _albedo_cached(model: Keyed, mu: tuple | int, phi_deg: float, method: tuple) -> dict:
    mu_values = np.asarray(mu, dtype=float) if isinstance(mu, tuple) else np.linspace(0.0, 1.0, mu)
    data = freeze(quantities.albedo_curve(model.value.brdf(), mu_values, phi_deg, **dict(method)))
    b = budget.current()
    data["complete"] = not (b and b.notes)
    if not data["complete"]:
        data["note"] = "; ".join(b.notes) + " (setting BRDF_MAX_SECONDS)"
    return data


def compute(spec: ModelSpec, q) -> dict:
    """E(μ) and E_avg, from a bounded cache keyed by the model and the request: the
    quadrature is the one computation here that takes long enough to be worth keeping
    (tenths of a second against the milliseconds of a lookup), and a browser that
    revalidates with If-None-Match makes the server rebuild the body to compare tags.
    A cached answer says so (``cached``, ``computed_seconds``)."""
    mu = tuple(q.mu) if q.mu is not None else q.n
    data, hit = _albedo_cached.lookup(Keyed(spec, spec.key()), mu, q.phi_deg, _method_key(q))
    return mark_cached(data, hit)


def _method_key(q) -> tuple:
    """The method's arguments, only those that change its result (the cache key): the
    seed of a quadrature is not part of it. tol always is: E_avg is computed to it."""
    args = {"method": q.method, "tol": q.tol}
    if q.method == "quadrature":
        args["order"] = q.order
    elif q.method.startswith("mc_"):
        args.update(samples=q.samples, seed=q.seed)
    return tuple(args.items())


def limits(q, s: Settings) -> None:
    if q.mu is not None and len(q.mu) == 0:
        raise ParameterError("mu", "mu must hold at least one value in [0, 1]")
    count = len(q.mu) if q.mu is not None else q.n
    where = "mu" if q.mu is not None else "n"
    limit(where, count, s.max_albedo_points, "BRDF_MAX_ALBEDO_POINTS")
    if q.method.startswith("mc_") and count * q.samples > s.max_mc_evaluations:
        raise ParameterError("samples", f"{count} μ values × samples={q.samples} = "
                             f"{count * q.samples} Monte Carlo evaluations exceed the limit "
                             f"{s.max_mc_evaluations} (setting BRDF_MAX_MC_EVALUATIONS)")
    brdf = schemas.spec_of(q).brdf()
    fresnel = getattr(brdf, "fresnel", None)
    if q.method == "table" and fresnel is not None and fresnel.schlick_basis() is None:
        # decided here, before any work (the table method would refuse it after computing)
        raise ParameterError("method", "method=table needs a Fresnel on the Schlick basis (none "
                             f"or schlick: E is tabulated per basis function); got fresnel={fresnel.name}")
    worst = max_evaluations(brdf, count)
    if worst > s.max_evaluations:
        raise ParameterError(where, f"{count} μ values may need up to {worst:.3g} integrand "
                             "evaluations (every μ refined to the highest order); the limit is "
                             f"{s.max_evaluations:.3g} (setting BRDF_MAX_EVALUATIONS): ask for fewer")


VIEW = View(
    "albedo", "Directional albedo E(μ)",
    "E(μ), the share of light a surface reflects from each direction, by quadrature, "
    "Monte Carlo or table, with its error and cost; with compensation also the "
    "single-scattering E.",
    schemas.AlbedoQuery, schemas.AlbedoFigureQuery, compute,
    lambda data, spec, q: albedo_figure(data, spec.values, getattr(q, "y_range", "fit")),
    limits,
    overlayable=True)
