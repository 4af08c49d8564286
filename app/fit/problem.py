"""What is fitted: the free parameters (bounds from the registry, log-scaled where the
registry says so), the measured points, and the error measure.

Measures (residual r per point; least squares minimises Σ r²):

- ``log``: r = ln(f_model + ε) − ln(f_data + ε). Every decade counts alike: the dim
  tails weigh as much as the specular peak — the shape of the lobe.
- ``relative``: r = (f_model − f_data)/(f_data + ε). Like log for small errors, but an
  overshoot costs more than an undershoot: it keeps a model from exceeding faint data.
- ``cosine``: r = (f_model − f_data)·cos θ_l. The reflected radiance per unit irradiance
  (Ngan et al. 2005's cosine weighting): the bright peak dominates, grazing light counts
  little — what a rendering shows.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..model import COMMON_PARAMS, choice_params, make_spec
from ..datasets.channel import model_f
from ..datasets.dataset import term_of_model
from ..physics.params import Param

#: ε of the log and relative measures, in 1/sr: one count of MERL's red channel
#: (1/1500 ≈ 6.7e-4 sr⁻¹), below which measured values are quantisation, not signal.
FLOOR = 1.0 / 1500.0
MEASURES = ("log", "relative", "cosine")
#: start of a free second-lobe weight given as 0, where α₂ would have no effect (and no
#: gradient): the middle of its range
LOBE_MIX_START = 0.5
#: parameters that are not free (another spelling of alpha, alpha_y)
NOT_FREE = {"roughness", "anisotropy"}


def free_params(model: dict) -> dict[str, Param]:
    """Every parameter of ``model``'s family that a fit may free, by name."""
    out = {p.name: p for p in COMMON_PARAMS if p.name not in NOT_FREE}
    for option in ("ndf", "fresnel"):
        spec_name = model.get(option) or make_spec().values[option]
        out.update({p.name: p for p in choice_params(option, spec_name)})
    return out


@dataclass(frozen=True)
class Problem:
    """Points (l, v, f) or a term against its angle, a fixed model and free parameters."""
    model: dict                 # fixed part, as make_spec takes it
    free: tuple[Param, ...]
    start: np.ndarray           # in the parameters' own units
    measure: str
    target: np.ndarray          # data values
    l: np.ndarray | None = None
    v: np.ndarray | None = None
    term: str | None = None     # "D", "G1", "F" for term data
    angle_deg: np.ndarray | None = None
    channel: str | None = None  # the data's channel: a coloured model is fitted in it

    def spec(self, x: np.ndarray):
        values = dict(self.model)
        values.update({p.name: float(np.clip(xi, p.lo, p.hi)) for p, xi in zip(self.free, x)})
        return make_spec(**values)

    def predict(self, x: np.ndarray) -> np.ndarray:
        brdf = self.spec(x).brdf()
        if self.term is None:
            return model_f(brdf, self.l, self.v, self.channel)
        return term_of_model(brdf, self.term, self.angle_deg)

    def residual(self, x: np.ndarray) -> np.ndarray:
        model = self.predict(x)
        if self.measure == "log":
            return np.log(model + FLOOR) - np.log(self.target + FLOOR)
        if self.measure == "relative":
            return (model - self.target) / (self.target + FLOOR)
        weight = self.l[..., 2] if self.term is None else 1.0
        return (model - self.target) * weight


def make_problem(model: dict, free: list[str], measure: str, **points) -> Problem:
    """Validate the fit's request (each refusal names the field) and build the problem."""
    if measure not in MEASURES:
        raise ParameterError("measure", f"measure must be one of {', '.join(MEASURES)}; got {measure!r}",
                             loc="body")
    try:
        base = make_spec(**model)
    except ParameterError as exc:
        raise ParameterError(f"model.{exc.param}", exc.message, loc="body") from None
    family = base.family.name
    if "alpha" not in base.family.own_names():     # a fit frees α, F₀, k_d…: the microfacet parameters
        raise ParameterError("model.model", f"fits are offered for the microfacet model only; "
                                            f"model={family} cannot be fitted (its parameters are "
                                            "not the microfacet ones a fit would free)", loc="body")
    allowed = free_params(base.values)
    if not free:
        raise ParameterError("free", f"name at least one free parameter: {', '.join(allowed)}", loc="body")
    for name in free:
        if name not in allowed:
            raise ParameterError("free", f"{name!r} is not a free parameter of this model; it has "
                                         f"{', '.join(allowed)}", loc="body")
    if len(set(free)) != len(free):
        raise ParameterError("free", "a parameter is named twice", loc="body")
    if "lobe_mix" in free and base.values.get("alpha2") is None and "alpha2" not in free:
        raise ParameterError("free", "a free lobe_mix needs alpha2, the second lobe's roughness: "
                                     "give it in model or free it too", loc="body")
    params = tuple(allowed[n] for n in free)
    start = np.array([base.values.get(p.name) if base.values.get(p.name) is not None else p.default
                      for p in params], dtype=float)
    if "alpha_y" in free and base.values.get("alpha_y") is None:
        start[free.index("alpha_y")] = base.values["alpha"]
    if "lobe_mix" in free and base.values["lobe_mix"] == 0:
        start[free.index("lobe_mix")] = LOBE_MIX_START
    # alpha given as roughness: freeing alpha replaces that spelling
    spelled_by_r = {"roughness", "anisotropy", "aniso_map"} if {"alpha", "alpha_y"} & set(free) else set()
    fixed = {k: v for k, v in model.items() if k not in free and k not in spelled_by_r}
    if spelled_by_r and "alpha" not in free:
        fixed["alpha"] = base.values["alpha"]
    return Problem(fixed, params, start, measure, **points)
