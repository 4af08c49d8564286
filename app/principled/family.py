"""``model=principled``: the principled BRDF's entry in the model registry
(app/model/family.py): its parameters and options, query form, validation (spec.py),
BRDF (material.py), the views that draw it, its albedo methods and lobe-wise albedo.
"""
from __future__ import annotations

from typing import Annotated, Literal, Optional

import numpy as np
from pydantic import BeforeValidator, Field

from ..model.family import Family, every_view_but, param_fields
from . import albedo, spec, title
from .colour import colour_text
from .params import BASE_COLOR_DEFAULT, OPTIONS, PARAMS

NAME = "principled"

#: Views that refuse the principled model (422 naming ``model``), and why: each varies the
#: microfacet model's own choices, which the principled model fixes.
MICROFACET_ONLY = {
    "advise": "It searches for cheaper microfacet choices (D, G2, Fresnel, α) for a scene; "
              "the principled model fixes those.",
    "checks": "Its identities vary the microfacet model's own terms (G2, Fresnel, k_d); "
              "the principled model fixes those.",
}
#: Choices for isotropic roughness only (anisotropic = 0): make_values refuses them otherwise.
ISOTROPIC_ONLY = {("principled_multiscatter", "kulla_conty")}
#: integrate/'s methods that apply: the quadrature (each lobe by its own rule, the
#: specular lobes by the adaptive albedo quadrature) and Monte Carlo on f itself. The
#: E(μ, α) tables hold a single GGX lobe with one Fresnel, not this sum of lobes: no
#: table, and so no auto (which picks a table when one applies).
ALBEDO_METHODS = ("quadrature", "mc_uniform", "mc_cosine", "mc_ndf", "mc_vndf")


def query_fields() -> dict:
    """base_color, roughness, the parameters and the options (all optional: absent = the
    paper's default)."""
    fields: dict = {"base_color": (Optional[Annotated[str, BeforeValidator(colour_text)]], Field(
        None, examples=["0.82,0.67,0.16"],
        description="model=principled: base colour as r,g,b in [0, 1] (linear), a JSON list "
                    "[r, g, b], or #rrggbb / #rgb (sRGB-encoded, decoded to linear by the sRGB "
                    "curve, IEC 61966-2-1); default 0.82,0.67,0.16"))}
    fields.update(param_fields((spec.ROUGHNESS, *PARAMS), NAME))
    for name, (label, choices, default) in OPTIONS.items():
        fields[name] = (Optional[Literal[tuple(choices)]], Field(
            None, description=f"model=principled: {label}: {', '.join(choices)}; default {default}"))
    return fields


#: The parameter whose value > 0 makes the roughness anisotropic (the page: which
#: choices apply, at which azimuth the curves are taken).
ANISOTROPY_PARAM = "anisotropic"
#: What is drawn (changed while looking) before what changes the model.
SHOWN = ("lobe", "channel")


def _choice(option: str, c) -> dict:
    out = {"name": c.name, "label": c.label, "description": c.description}
    if (option, c.name) in ISOTROPIC_ONLY:
        out["isotropic_only"] = True
        out["requires_zero"] = ANISOTROPY_PARAM
    return out


def catalogue() -> dict:
    """The parameters (base_color a colour), ranges, defaults and options, the roughness
    and anisotropy parameters by name, and the sidebar's sections (names in order)."""
    params = [spec.ROUGHNESS, *PARAMS]
    return {"colors": [{"name": "base_color", "label": "base colour", "default": list(BASE_COLOR_DEFAULT),
                        "lo": 0.0, "hi": 1.0, "description": "Base colour r,g,b in [0, 1] (linear, or "
                        "decoded as sRGB-like: see its encoding below)"}],
            "params": [p.as_dict() for p in params],
            "options": {name: {"label": label, "default": default,
                               "choices": [_choice(name, c) for c in choices.values()]}
                        for name, (label, choices, default) in OPTIONS.items()},
            "roughness_param": spec.ROUGHNESS.name, "anisotropy_param": ANISOTROPY_PARAM,
            "sections": [{"title": "Principled BRDF", "names": [*SHOWN, "base_color", *(p.name for p in params)]},
                         {"title": "Where implementations differ",
                          "names": [name for name in OPTIONS if name not in SHOWN]}]}


def lobe_albedo(model, mu) -> dict:
    """E(μ) per lobe and channel (app/principled/albedo.py)."""
    return albedo.albedo(model.brdf(), np.asarray(mu, dtype=float))


FAMILY = Family(
    NAME, "Principled BRDF (Burley 2012)",
    "Disney's principled BRDF: base colour, metallic, roughness, sheen, clearcoat… each in [0, 1].",
    "Burley 2012, Physically-Based Shading at Disney; docs/principled.md",
    spec.make_values, spec.brdf, spec.as_query, query_fields, catalogue,
    views=every_view_but(MICROFACET_ONLY), albedo_methods=ALBEDO_METHODS, lobe_albedo=lobe_albedo,
    names=spec.NAMES, title=title.title, differences=title.differences)
