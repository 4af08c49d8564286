"""From flat parameters (as the API and the CLI spell them) to a BRDF.

Knows the registries; raises :class:`ModelError` naming the offending parameter and
what it allows, which the API turns into an HTTP 422.
"""
from __future__ import annotations

from dataclasses import dataclass

from .physics.brdf import BRDF
from .physics.fresnel import FRESNELS
from .physics.g2 import G2_FORMS
from .physics.masking import MASKINGS
from .physics.ndf import ALPHA, ALPHA_Y, NDFS
from .physics.params import Param

KD = Param("kd", "k_d (Lambertian weight)", 0.0, 1.0, 0.0,
           "Weight of a Lambertian term kd/π added to the specular lobe.")

#: Continuous parameters every model takes.
COMMON_PARAMS: tuple[Param, ...] = (ALPHA, ALPHA_Y, KD)

#: The discrete options with their registries and defaults.
OPTIONS = {
    "ndf": ("Normal distribution D", NDFS, "ggx"),
    "masking": ("Masking Λ, G1", MASKINGS, "smith"),
    "g2": ("Masking-shadowing G2", G2_FORMS, "height_correlated"),
    "fresnel": ("Fresnel F", FRESNELS, "schlick"),
}


class ModelError(ValueError):
    """A parameter that the chosen model does not accept."""

    def __init__(self, param: str, message: str):
        super().__init__(message)
        self.param = param
        self.message = message


def choice_params(option: str, name: str) -> tuple[Param, ...]:
    """Parameters that belong to one choice of an option (an NDF's shape, Schlick's f0)."""
    entry = OPTIONS[option][1][name]
    return tuple(getattr(entry, "shape_params", ()) or getattr(entry, "params", ()))


def choice_param_names() -> dict[str, dict[str, Param]]:
    """Every choice-specific parameter name → {choice: Param} (a name may be shared)."""
    out: dict[str, dict[str, Param]] = {}
    for option, (_, registry, _) in OPTIONS.items():
        for name in registry:
            for p in choice_params(option, name):
                out.setdefault(p.name, {})[f"{option}={name}"] = p
    return out


@dataclass(frozen=True)
class ModelSpec:
    """The validated, flat description of a model: what URLs and API calls carry."""
    values: dict

    def brdf(self) -> BRDF:
        v = self.values
        shape = {p.name: v[p.name] for p in choice_params("ndf", v["ndf"]) if v.get(p.name) is not None}
        fresnel_values = {p.name: v[p.name] for p in choice_params("fresnel", v["fresnel"])
                          if v.get(p.name) is not None}
        ndf = NDFS[v["ndf"]](v["alpha"], v.get("alpha_y"), **shape)
        return BRDF(ndf, MASKINGS[v["masking"]], G2_FORMS[v["g2"]],
                    FRESNELS[v["fresnel"]](**fresnel_values), v.get("kd", 0.0))


def make_spec(**given) -> ModelSpec:
    """Validate flat parameters: options known, values in range, each choice parameter
    used only with the choice it belongs to. Missing values take their defaults."""
    values: dict = {}
    for option, (_, registry, default) in OPTIONS.items():
        name = given.pop(option, None) or default
        if name not in registry:
            raise ModelError(option, f"{option} must be one of {', '.join(registry)}; got {name!r}")
        values[option] = name
    for p in COMMON_PARAMS:
        x = given.pop(p.name, None)
        if x is None:
            values[p.name] = None if p is ALPHA_Y else p.default
            continue
        _check_range(p, x)
        values[p.name] = float(x)
    masking = MASKINGS[values["masking"]]
    if masking.applies_to is not None and values["ndf"] not in masking.applies_to:
        raise ModelError("masking", f"masking={values['masking']} applies to ndf "
                         f"{', '.join(masking.applies_to)} only, not {values['ndf']}")
    owners = choice_param_names()
    for name, x in given.items():
        if x is None:
            continue
        if name not in owners:
            raise ModelError(name, f"unknown model parameter {name!r}")
        chosen = [key for key in owners[name] if values[key.split('=')[0]] == key.split('=')[1]]
        if not chosen:
            raise ModelError(name, f"{name} applies only with {' or '.join(owners[name])}")
        _check_range(owners[name][chosen[0]], x)
        values[name] = float(x)
    for option in ("ndf", "fresnel"):
        for p in choice_params(option, values[option]):
            values.setdefault(p.name, p.default)
    return ModelSpec(values)


def _check_range(p: Param, x) -> None:
    try:
        ok = p.contains(float(x))
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ModelError(p.name, f"{p.name} must be a number in {p.range_text()}; got {x!r}")
