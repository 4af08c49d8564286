"""The advice view: the cheaper choices of a model over the range a scene uses (roughness,
angles), their albedo error and measured cost, and the cheapest within a tolerance
(app/analysis/advise.py)."""
from __future__ import annotations

from typing import Annotated, Literal

from pydantic import Field

from ..analysis.advise import RESULT_CACHE_ENTRIES, Scene, advise, is_anisotropic
from ..config import Settings
from ..figures.advise import advise_figure
from ..integrate.cache import Keyed, complete_only, mark_cached
from ..physics.ndf import ALPHA
from ..errors import ParameterError
from ..model import family_of
from . import schemas
from .view import View


class AdviseQuery(schemas.ModelQuery):
    tol: Annotated[float, Field(ge=1e-4, le=0.5, description=(
        "largest acceptable error: absolute error of the directional albedo E(μ) (energy "
        "per direction, in [0, 1]) anywhere in the range"))] = 1e-2
    alpha_min: Annotated[float, Field(ge=ALPHA.lo, le=ALPHA.hi, description=(
        "smallest roughness α the scene uses (replaces the model's α)"))] = 0.05
    alpha_max: Annotated[float, Field(ge=ALPHA.lo, le=ALPHA.hi, description=(
        "largest roughness α the scene uses; ≥ alpha_min"))] = 1.0
    theta_max_deg: Annotated[float, Field(ge=0.0, le=90.0, description=(
        "largest polar angle of view and light in the scene, degrees, [0, 90]"))] = 90.0
    metric: Annotated[Literal["albedo", "pointwise"], Field(description=(
        "albedo: the largest absolute error of E(μ), energy per direction; pointwise: the "
        "largest relative error of f itself over the range of α and both angles, with a "
        "floor for f near zero that the answer states (metric_text)"))] = "albedo"
    albedo_methods: Annotated[bool, Field(description=(
        "also rate the albedo methods (table, Monte Carlo) against the quadrature for the "
        "recommended model; a table's first build takes seconds"))] = False


def _check_advise(q: AdviseQuery, s: Settings):
    if q.alpha_min > q.alpha_max:
        raise ParameterError("alpha_min", f"alpha_min={q.alpha_min:g} is above alpha_max="
                                      f"{q.alpha_max:g}: the range needs alpha_min ≤ alpha_max")
    given = schemas.model_values(q)
    if "alpha" not in family_of(given).own_names():   # it varies alpha, alpha_y
        raise ParameterError("model", "this analysis changes alpha, alpha_y of a microfacet "
                             "model; it applies to model=microfacet only")
    if is_anisotropic(schemas.spec_of(q).values):
        name = "anisotropy" if "anisotropy" in given else "alpha_y"
        raise ParameterError(name, f"{name}: advise is for isotropic models (alpha_y = alpha): the "
                               "scene's range replaces one α, and the albedo metric, the tables "
                               "and Kulla-Conty are isotropic")


@complete_only(RESULT_CACHE_ENTRIES, complete=lambda data: data["complete"])
def _cached(given: Keyed, tol: float, scene: Scene, albedo_methods: bool, metric: str) -> dict:
    """``given.value``: (the request's model parameters, the spec built from them)."""
    model, spec = given.value
    return advise(model, tol, scene, albedo_methods, spec, metric)


def _compute(spec, q: AdviseQuery) -> dict:
    """The advice, from a bounded cache of complete results: the page asks for the figure
    and an export for the data of the same request, and the timing is worth keeping."""
    given = schemas.model_values(q)
    scene = Scene(q.alpha_min, q.alpha_max, q.theta_max_deg)
    data, hit = _cached.lookup(Keyed((given, spec), tuple(sorted(given.items()))), q.tol, scene,
                               q.albedo_methods, q.metric)
    return mark_cached(data, hit)


VIEW = View(
    "advise", "Advice: a cheaper model",
    "The cheaper choices of the model over the scene's range of α and θ, each with its "
    "largest albedo error and measured relative cost, and the cheapest within tol.",
    AdviseQuery, AdviseQuery, _compute,
    lambda data, spec, q: advise_figure(data, spec.values),
    _check_advise,
    layout="strip",
    refuses_material="advise compares one Fresnel per choice, not a measured material's three "
                     "channels; give fresnel=conductor with ior and k (or fresnel=dielectric "
                     "with ior) instead")
