"""``model=principled`` from flat parameters (the API's and the CLI's spelling): the
family's validation, called by app/model's one make_spec. Values carry the principled
parameters and options plus, for code that reads any model's specular terms, the GGX lobe's own description
(ndf, masking, g2, fresnel, alpha, alpha_y, f0), which the principled model derives.
"""
from __future__ import annotations

import numpy as np

from ..errors import ParameterError
from ..model.family import check_range
from ..physics.params import Param
from .colour import parse_color
from .material import Principled, principled_brdf
from .params import BASE_COLOR_DEFAULT, LUMINANCE, OPTIONS, PARAMS

#: The principled roughness r (α = r², Burley 2012); the API's common ``roughness``.
ROUGHNESS = Param("roughness", "roughness r", 0.0, 1.0, 0.5,
                  "Perceptual roughness r: the specular α = r² (floored at 0.001), the diffuse's retro-reflection.")
#: Everything model=principled takes (besides ``model`` itself).
NAMES = ("base_color", ROUGHNESS.name, *(p.name for p in PARAMS), *OPTIONS)


def make_values(given: dict) -> dict:
    """Validated values of a principled model from the parameters given (no None, no model)."""
    for name in given:
        if name not in NAMES:
            raise ParameterError(name, f"{name} does not apply to model=principled (it takes "
                                       f"{', '.join(NAMES)})")
    values: dict = {"model": "principled",
                    "base_color": parse_color(given.get("base_color", BASE_COLOR_DEFAULT))}
    for p in (ROUGHNESS, *PARAMS):
        values[p.name] = check_range(p, given.get(p.name, p.default))
    for name, (_, choices, default) in OPTIONS.items():
        chosen = given.get(name, default)
        if chosen not in choices:
            raise ParameterError(name, f"{name} must be one of {', '.join(choices)}; got {chosen!r}")
        values[name] = chosen
    if values["principled_multiscatter"] == "kulla_conty" and values["anisotropic"] > 0:
        raise ParameterError("principled_multiscatter", "principled_multiscatter=kulla_conty is for "
                             "isotropic roughness only (anisotropic = 0): its E(μ, α) table is isotropic")
    m = material(values)
    ax, ay = m.alphas
    values.update(ndf="ggx", masking="smith", g2=values["principled_g2"], fresnel="schlick",
                  multiscatter="none", diffuse="lambert", alpha=ax, alpha_y=None if ax == ay else ay,
                  kd=0.0, f0=float(np.clip(np.dot(LUMINANCE, m.specular_color), 0.0, 1.0)), f90=1.0,
                  fresnel_p=5.0, alpha2=None, lobe_mix=0.0, anisotropy=None)
    return values


def material(values: dict) -> Principled:
    return Principled(base_color=tuple(values["base_color"]),
                      roughness=values["roughness"], **{p.name: values[p.name] for p in PARAMS},
                      options={k: values[k] for k in ("principled_g2", "principled_diffuse",
                                                      "principled_multiscatter", "base_color_space")})


def brdf(values: dict):
    return principled_brdf(material(values), values["lobe"], values["channel"])


def as_query(values: dict) -> dict:
    """The model as make_spec takes it back: every principled name, base_color as r,g,b."""
    out = {"model": "principled", **{k: values[k] for k in NAMES if k != "base_color"}}
    out["base_color"] = ",".join(f"{c:g}" for c in values["base_color"])
    return out
