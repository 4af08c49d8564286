"""The views: for each, its query model, the arrays it computes and its figure.

Each view gives a data route ``/api/v1/{name}`` and a figure route
``/api/v1/figures/{name}``. Limits are checked here, before any work is done.
"""
from __future__ import annotations

import importlib
import pkgutil
from dataclasses import dataclass
from pathlib import Path
from typing import Callable

import numpy as np

from .. import figures, quantities
from ..config import Settings
from ..integrate import budget
from ..integrate.albedo import max_evaluations
from ..integrate.cache import Keyed, complete_only, freeze
from ..model import ModelSpec, make_spec
from . import schemas
from ..errors import ParameterError


#: albedo results kept (each a few kB: E, E_error at ≤ BRDF_MAX_ALBEDO_POINTS μ values)
ALBEDO_CACHE_ENTRIES = 256


def _limit(name: str, value: int, limit: int, env: str) -> None:
    if value > limit:
        raise ParameterError(name, f"{name}={value} exceeds the limit {limit} (setting {env})")


@dataclass(frozen=True)
class View:
    name: str
    summary: str
    query: type
    figure_query: type
    check_limits: Callable[[object, Settings], None]
    compute: Callable[[ModelSpec, object], dict]
    figure: Callable[[dict, ModelSpec, object], dict]

    def check(self, q, settings: Settings) -> None:
        """Refuse the query before any work: a parameter given where it does not apply
        (schemas.applies_to), then the view's own limits."""
        schemas.applies_where_given(q)
        self.check_limits(q, settings)


def _check_curve(q, s: Settings):
    _limit("n", q.n, s.max_curve_points, "BRDF_MAX_CURVE_POINTS")


def _check_grid(q, s: Settings):
    _limit("n_theta×n_phi", q.n_theta * q.n_phi, s.max_grid_points, "BRDF_MAX_GRID_POINTS")


def _check_square_grid(q, s: Settings):
    if q.n * q.n > s.max_grid_points:
        raise ParameterError("n", f"n={q.n} gives n²={q.n * q.n} grid points, above the limit "
                              f"{s.max_grid_points} (setting BRDF_MAX_GRID_POINTS)")


@complete_only(ALBEDO_CACHE_ENTRIES, complete=lambda data: data["complete"])
def _albedo_cached(model: Keyed, mu: tuple | int, phi_deg: float, method: tuple) -> dict:
    mu_values = np.asarray(mu, dtype=float) if isinstance(mu, tuple) else np.linspace(0.0, 1.0, mu)
    data = freeze(quantities.albedo_curve(model.value.brdf(), mu_values, phi_deg, **dict(method)))
    b = budget.current()
    data["complete"] = not (b and b.notes)
    if not data["complete"]:
        data["note"] = "; ".join(b.notes) + " (setting BRDF_MAX_SECONDS)"
    return data


def _albedo(spec: ModelSpec, q) -> dict:
    """E(μ) and E_avg, from a bounded cache keyed by the model and the request: the
    quadrature is the one computation here that takes long enough to be worth keeping
    (tenths of a second against the milliseconds of a lookup), and a browser that
    revalidates with If-None-Match makes the server rebuild the body to compare tags."""
    mu = tuple(q.mu) if q.mu is not None else q.n
    key = tuple(sorted(spec.values.items()))
    return dict(_albedo_cached(Keyed(spec, key), mu, q.phi_deg, _method_key(q)))


def _method_key(q) -> tuple:
    """The method's arguments, only those that change its result (the cache key): the
    seed of a quadrature is not part of it. tol always is: E_avg is computed to it."""
    args = {"method": q.method, "tol": q.tol}
    if q.method == "quadrature":
        args["order"] = q.order
    elif q.method.startswith("mc_"):
        args.update(samples=q.samples, seed=q.seed)
    return tuple(args.items())


def _check_albedo(q, s: Settings):
    if q.mu is not None and len(q.mu) == 0:
        raise ParameterError("mu", "mu must hold at least one value in [0, 1]")
    count = len(q.mu) if q.mu is not None else q.n
    where = "mu" if q.mu is not None else "n"
    _limit(where, count, s.max_albedo_points, "BRDF_MAX_ALBEDO_POINTS")
    if q.method.startswith("mc_"):
        if count * q.samples > s.max_mc_evaluations:
            raise ParameterError("samples", f"{count} μ values × samples={q.samples} = "
                             f"{count * q.samples} Monte Carlo evaluations exceed the limit "
                             f"{s.max_mc_evaluations} (setting BRDF_MAX_MC_EVALUATIONS)")
    worst = max_evaluations(make_spec(**schemas.model_values(q)).brdf(), count)
    if worst > s.max_evaluations:
        raise ParameterError("mu" if q.mu is not None else "n",
                         f"{count} μ values may need up to {worst:.3g} integrand evaluations "
                         f"(every μ refined to the highest order); the limit is "
                         f"{s.max_evaluations:.3g} (setting BRDF_MAX_EVALUATIONS): ask for fewer")


VIEWS: dict[str, View] = {v.name: v for v in [
    View("ndf", "D(θ_m) at azimuth φ, θ_m = 0..90°",
         schemas.NdfQuery, schemas.NdfFigureQuery, _check_curve,
         lambda spec, q: quantities.ndf_curve(spec.brdf(), q.phi_deg, q.n, q.cosine),
         lambda data, spec, q: figures.ndf_figure(data, spec.values, q.log)),
    View("g1", "Λ(θ_v) and G1(θ_v) = 1/(1+Λ) for θ_v = 0..90°",
         schemas.CurveQuery, schemas.CurveQuery, _check_curve,
         lambda spec, q: quantities.g1_curve(spec.brdf(), q.phi_deg, q.n),
         lambda data, spec, q: figures.g1_figure(data, spec.values)),
    View("lobe", "f in the plane of incidence, θ_o = −90..90° (positive on the mirror side)",
         schemas.LobeQuery, schemas.LobeFigureQuery, _check_curve,
         lambda spec, q: quantities.lobe_curve(spec.brdf(), q.theta_i_deg, q.phi_i_deg, q.n, q.cosine),
         lambda data, spec, q: figures.lobe_figure(data, spec.values, q.theta_i_deg, q.log)),
    View("lobe3d", "f over the hemisphere of v (θ rows × φ columns)",
         schemas.Lobe3dQuery, schemas.Lobe3dFigureQuery, _check_grid,
         lambda spec, q: quantities.lobe_grid(spec.brdf(), q.theta_i_deg, q.phi_i_deg, q.n_theta, q.n_phi),
         lambda data, spec, q: figures.lobe3d_figure(data, spec.values, q.theta_i_deg, q.phi_i_deg, q.log)),
    View("albedo", "Directional albedo E(μ) by quadrature, Monte Carlo or table, with its error "
                   "and cost; with compensation also the single-scattering E",
         schemas.AlbedoQuery, schemas.AlbedoQuery, _check_albedo,
         lambda spec, q: _albedo(spec, q),
         lambda data, spec, q: figures.albedo_figure(data, spec.values)),
    View("g2", "G2(θ_l, θ_v) over θ_l, θ_v = 0..90° (rows θ_l) with v at azimuth φ from l",
         schemas.G2Query, schemas.G2Query, _check_square_grid,
         lambda spec, q: quantities.g2_grid(spec.brdf(), q.phi_deg, q.n),
         lambda data, spec, q: figures.g2_figure(data, spec.values, q.phi_deg)),
    View("fresnel", "F(θ_d) for θ_d = 0..90°; for Schlick also the exact dielectric of the "
                    "same F₀ and the error",
         schemas.FresnelQuery, schemas.FresnelQuery, _check_curve,
         lambda spec, q: quantities.fresnel_curve(spec.brdf(), q.n),
         lambda data, spec, q: figures.fresnel_figure(data, spec.values)),
    View("sphere", "A sphere under one directional light: L_o/E = f·cos θ_l per pixel "
                   "(rows y, columns x; null off the sphere)",
         schemas.SphereQuery, schemas.SphereFigureQuery, _check_square_grid,
         lambda spec, q: quantities.lit_sphere(spec.brdf(), q.theta_i_deg, q.phi_i_deg, q.n),
         lambda data, spec, q: figures.lit_sphere_figure(data, spec.values, q.theta_i_deg,
                                                         q.phi_i_deg, q.display, q.exposure)),
    View("slice", "f over θ_h × θ_d at fixed φ_h, φ_d (the Disney explorer's image slice; "
                  "rows θ_d, null below the horizon)",
         schemas.SliceQuery, schemas.SliceFigureQuery, _check_square_grid,
         lambda spec, q: quantities.half_difference_slice(spec.brdf(), q.phi_h_deg, q.phi_d_deg,
                                                          q.n, q.cosine),
         lambda data, spec, q: figures.slice_figure(data, spec.values, q.phi_d_deg, q.log)),
]}


def register(view: View) -> View:
    """Add a view: it gets its data, figure, compare and export routes, a panel on the
    page and a CLI figure kind. Views that are more than a few lines live in their own
    module ``app/api/view_<name>.py``, which calls this; those modules are imported below,
    so adding such a view is adding one file."""
    if view.name in VIEWS:
        raise ValueError(f"view {view.name!r} registered twice")
    VIEWS[view.name] = view
    return view


def _import_view_modules() -> None:
    for info in sorted(pkgutil.iter_modules([str(Path(__file__).parent)]),
                       key=lambda i: i.name):
        if info.name.startswith("view_"):
            importlib.import_module(f"{__package__}.{info.name}")


_import_view_modules()
