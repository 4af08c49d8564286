"""``model=microfacet``, the model registry's first family: a specular microfacet lobe
from the physics registries' choices (NDF, masking, G2, Fresnel, multiple scattering,
diffuse model) and the common parameters, from flat parameters (as the API and the CLI
spell them) to a BRDF. Raises :class:`ParameterError` naming the offending parameter and
what it allows, which the API turns into an HTTP 422.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Annotated, Callable, Literal, Optional

import numpy as np
from pydantic import AfterValidator, Field

from ..errors import ParameterError
from .. import materials
from ..integrate.compensation import MULTISCATTERS, compensated
from ..integrate.methods import METHODS, albedo_by
from ..physics.brdf import BRDF
from ..physics.diffuse import DIFFUSES
from ..physics.fresnel import FRESNELS
from ..physics.g2 import DEFAULT_LAMBDA_PHI, G2_FORMS, LAMBDA_PHIS
from ..physics.masking import MASKINGS
from ..physics.masking import REFERENCE as MASKING_REFERENCE
from ..physics.ndf import ALPHA, ALPHA_Y, NDFS
from ..physics.params import Param
from .family import Family, check_range

KD = Param("kd", "k_d (diffuse weight)", 0.0, 1.0, 0.0,
           "Weight ρ of the diffuse term added to the specular lobe (kd/π for Lambert).")
ROUGHNESS = Param("roughness", "r (perceptual roughness)", 0.01, 1.0, 0.5477225575051661,
                  "Perceptual roughness r, α = r² (Burley 2012): the other way to give α. "
                  "Not together with alpha/alpha_y.")
ANISOTROPY = Param("anisotropy", "anisotropy k", 0.0, 1.0, 0.0,
                   "Anisotropy of the roughness form, mapped to (α_x, α_y) by aniso_map.")
ALPHA2 = Param("alpha2", "α₂ (second lobe)", 1e-4, 1.0, 0.05,
               "Roughness of a second specular lobe with the same NDF (isotropic).", scale="log")
LOBE_MIX = Param("lobe_mix", "w (second-lobe weight)", 0.0, 1.0, 0.0,
                 "f_spec = (1 − w) f_spec(α) + w f_spec(α₂) (Kulla & Conty 2017's two lobes).")

#: Continuous parameters every model takes.
COMMON_PARAMS: tuple[Param, ...] = (ALPHA, ALPHA_Y, KD, ROUGHNESS, ANISOTROPY, ALPHA2, LOBE_MIX)
COMMON_NAMES = frozenset(p.name for p in COMMON_PARAMS)
#: Those that are absent unless given (absent alpha_y = isotropic, and so on).
OPTIONAL_PARAMS = frozenset({"alpha_y", "roughness", "anisotropy", "alpha2"})

#: The discrete options with their registries and defaults.
OPTIONS = {
    "ndf": ("Normal distribution D", NDFS, "ggx"),
    "masking": ("Masking Λ, G1", MASKINGS, "smith"),
    "g2": ("Masking-shadowing G2", G2_FORMS, "height_correlated"),
    "fresnel": ("Fresnel F", FRESNELS, "schlick"),
    "multiscatter": ("Multiple scattering", MULTISCATTERS, "none"),
    "diffuse": ("Diffuse f_d", DIFFUSES, "lambert"),
}


@dataclass(frozen=True)
class AnisoMap:
    name: str
    label: str
    description: str
    alphas: Callable  # (r, k) -> (α_x, α_y)


ANISO_MAPS = {m.name: m for m in [
    AnisoMap("burley", "Burley",
             "k_aspect = √(1 − 0.9k); α_x = r²/k_aspect, α_y = r² k_aspect (Burley 2012).",
             lambda r, k: (r * r / np.sqrt(1 - 0.9 * k), r * r * np.sqrt(1 - 0.9 * k))),
    AnisoMap("kulla_conty", "Kulla-Conty",
             "α_x = r²(1 + k), α_y = r²(1 − k) (Kulla & Conty 2017).",
             lambda r, k: (r * r * (1 + k), r * r * (1 - k))),
]}

#: Options that apply only in some models: name → (label, registry, default, applies(values), when).
SUB_OPTIONS = {
    "lambda_phi": ("λ(φ) of the direction-correlated G2", LAMBDA_PHIS, DEFAULT_LAMBDA_PHI,
                   lambda v: G2_FORMS[v["g2"]].needs_phi,
                   "g2=" + " or g2=".join(n for n, g in G2_FORMS.items() if g.needs_phi)),
    "aniso_map": ("Anisotropy map", ANISO_MAPS, "burley",
                  lambda v: v.get("roughness") is not None, "the roughness/anisotropy form"),
}


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


def as_query(v: dict) -> dict:
    """The model as make_spec (and every endpoint) takes it: every option named, the
    roughness as α (no roughness/anisotropy form), only parameters that apply, no
    derived values."""
    out = {name: v[name] for name in OPTIONS}
    out.update({p.name: v[p.name] for p in COMMON_PARAMS
                if p.name not in ("roughness", "anisotropy") and v.get(p.name) is not None})
    for option in ("ndf", "fresnel", "diffuse"):
        out.update({p.name: v[p.name] for p in choice_params(option, v[option])
                    if v.get(p.name) is not None})
    if v.get("lambda_phi") is not None:
        out["lambda_phi"] = v["lambda_phi"]
    return out


def edit(out: dict, changes: dict) -> dict:
    """The query ``out`` with ``changes``: the parameters of a replaced choice (Schlick's
    f0 when fresnel changes, λ(φ) when the new G2 does not take it) are dropped."""
    for option in ("ndf", "fresnel", "diffuse"):
        if option in changes and changes[option] != out.get(option):
            for p in choice_params(option, out[option]):
                out.pop(p.name, None)
    out.update(changes)
    if not G2_FORMS[out["g2"]].needs_phi:
        out.pop("lambda_phi", None)
    return out


def brdf(v: dict) -> BRDF:
    shape = {p.name: v[p.name] for p in choice_params("ndf", v["ndf"]) if v.get(p.name) is not None}
    fresnel_values = {p.name: v[p.name] for p in choice_params("fresnel", v["fresnel"])
                      if v.get(p.name) is not None}
    fresnel = (materials.MaterialFresnel(v["material"]) if v.get("material")
               else FRESNELS[v["fresnel"]](**fresnel_values))
    ndf_class = NDFS[v["ndf"]]
    lobe2 = ndf_class(v["alpha2"], None, **shape) if v.get("alpha2") is not None else None
    lambda_phi = LAMBDA_PHIS[v["lambda_phi"]].fn if v.get("lambda_phi") else None
    out = BRDF(ndf_class(v["alpha"], v.get("alpha_y"), **shape), MASKINGS[v["masking"]],
               G2_FORMS[v["g2"]], fresnel, v.get("kd", 0.0),
               lambda_phi=lambda_phi, lobe2=lobe2, lobe_mix=v.get("lobe_mix", 0.0),
               diffuse=_diffuse(v))
    if v.get("multiscatter") == "kulla_conty":
        return compensated(out)
    return out


def _diffuse(v: dict):
    """The diffuse model of ``v``, None for Lambert (the BRDF's own kd/π). Burley and
    Hammon take the specular roughness: α = √(α_x α_y), the isotropic α of equal area."""
    name = v.get("diffuse", "lambert")
    if name == "lambert":
        return None
    alpha = float(np.sqrt(v["alpha"] * (v.get("alpha_y") or v["alpha"])))
    return DIFFUSES[name](alpha=alpha, **{p.name: v[p.name] for p in choice_params("diffuse", name)
                                          if v.get(p.name) is not None})


def make_values(given: dict) -> dict:
    """Validate flat parameters: options known, values in range, each choice parameter
    used only with the choice it belongs to, one roughness form. Missing values take
    their defaults."""
    given = dict(given)
    material = _material_fresnel(given)
    explicit_alpha = [n for n in ("alpha", "alpha_y") if n in given]
    values: dict = {}
    for option, (_, registry, default) in OPTIONS.items():
        name = given.pop(option, default)
        if name not in registry:
            raise ParameterError(option, f"{option} must be one of {', '.join(registry)}; got {name!r}")
        values[option] = name
    for p in COMMON_PARAMS:
        if p.name in given:
            check_range(p, given[p.name])
            values[p.name] = float(given.pop(p.name))
        else:
            values[p.name] = None if p.name in OPTIONAL_PARAMS else p.default
    _roughness_form(values, given, explicit_alpha)
    for name, (_, registry, default, applies, when) in SUB_OPTIONS.items():
        chosen = given.pop(name, None)
        if not applies(values):
            if chosen is not None:
                raise ParameterError(name, f"{name} applies only with {when}")
            continue
        if chosen is not None and chosen not in registry:
            raise ParameterError(name, f"{name} must be one of {', '.join(registry)}; got {chosen!r}")
        values[name] = chosen or default
    if values["roughness"] is not None:
        _apply_aniso_map(values)
    if values["lobe_mix"] > 0 and values["alpha2"] is None:
        raise ParameterError("lobe_mix", "lobe_mix > 0 needs alpha2, the second lobe's roughness")
    _check_applicability(values)
    owners = choice_param_names()
    for name, x in given.items():
        if name not in owners:
            raise ParameterError(name, f"unknown model parameter {name!r}")
        chosen = [key for key in owners[name] if values[key.split('=')[0]] == key.split('=')[1]]
        if not chosen:
            raise ParameterError(name, f"{name} applies only with {' or '.join(owners[name])}")
        check_range(owners[name][chosen[0]], x)
        values[name] = float(x)
    for option in ("ndf", "fresnel", "diffuse"):
        for p in choice_params(option, values[option]):
            values.setdefault(p.name, p.default)
    if material is not None:        # its RGB index replaces the scalar one
        for p in choice_params("fresnel", values["fresnel"]):
            values.pop(p.name, None)
        values["material"] = material
    return values


def _material_fresnel(given: dict) -> str | None:
    """``material=<slug>`` (app/materials.py) sets the Fresnel option to its kind; its own
    RGB index replaces fresnel's parameters, which may not be given with it."""
    slug = given.pop("material", None)
    if slug is None:
        return None
    record = materials.material(slug)
    for name in ("fresnel", *choice_param_names()):
        if name in given and (name == "fresnel" or any(k.startswith("fresnel=") for k in choice_param_names()[name])):
            raise ParameterError(name, f"{name} is set by material={slug}: give one or the other")
    given["fresnel"] = record["kind"]
    return slug


def _roughness_form(values: dict, given: dict, explicit_alpha: list) -> None:
    uses_r = values["roughness"] is not None or values["anisotropy"] is not None or "aniso_map" in given
    if not uses_r:
        return
    if explicit_alpha:
        raise ParameterError(explicit_alpha[0], "give either alpha/alpha_y or roughness/anisotropy/aniso_map, "
                                      "not both")
    if values["roughness"] is None:
        values["roughness"] = ROUGHNESS.default
    if values["anisotropy"] is None:
        values["anisotropy"] = ANISOTROPY.default


def _apply_aniso_map(values: dict) -> None:
    """(r, k) → (α_x, α_y), converted once, here, at the edge (docs/conventions.md §4)."""
    ax, ay = ANISO_MAPS[values["aniso_map"]].alphas(values["roughness"], values["anisotropy"])
    for name, a in (("alpha", ax), ("alpha_y", ay)):
        if not ALPHA.contains(float(a)):
            raise ParameterError("anisotropy", f"roughness={values['roughness']:g} and anisotropy="
                             f"{values['anisotropy']:g} give {name}={float(a):.4g}, outside "
                             f"{ALPHA.range_text()}")
    values["alpha"] = float(ax)
    values["alpha_y"] = None if ax == ay else float(ay)


def _check_applicability(values: dict) -> None:
    ndf = values["ndf"]
    for option in ("masking", "g2"):
        entry = OPTIONS[option][1][values[option]]
        if entry.applies_to is not None and ndf not in entry.applies_to:
            raise ParameterError(option, f"{option}={values[option]} applies to ndf "
                             f"{', '.join(entry.applies_to)} only, not {ndf}")
    g2 = G2_FORMS[values["g2"]]
    anisotropic = values["alpha_y"] is not None and values["alpha_y"] != values["alpha"]
    if getattr(g2, "isotropic_only", False) and anisotropic:
        raise ParameterError("g2", f"g2={values['g2']} is for isotropic roughness only (alpha_y = alpha)")
    masking = MASKINGS[values["masking"]]
    if (values.get("multiscatter") == "kulla_conty" and masking.uses_ndf_Lambda
            and not NDFS[ndf].smith_exact):
        raise ParameterError("multiscatter", f"multiscatter=kulla_conty needs the NDF's exact Smith Λ: "
                                         f"ndf={ndf} with masking={masking.name} uses an approximate Λ "
                                         f"whose albedo exceeds 1 (use masking={MASKING_REFERENCE})")
    if anisotropic and values.get("multiscatter") == "kulla_conty":
        raise ParameterError("multiscatter", "multiscatter=kulla_conty is for isotropic roughness only "
                                         "(alpha_y = alpha): its E(μ, α) table is isotropic")
    if anisotropic and not NDFS[ndf].anisotropic:
        raise ParameterError("alpha_y", f"ndf={ndf} is isotropic only: it is not shape-invariant, "
                                    "so it has no anisotropic form")


def _material_slug(value):
    """A known material slug, else a ValueError that suggests the nearest (422)."""
    if value is not None and value not in materials.materials():
        raise ValueError(materials.unknown_material(value))
    return value


def query_fields() -> dict:
    """One query field per option and parameter the physics registries declare, so a new
    NDF (or a new shape parameter) appears in the API, its validation and ``/docs`` with
    no change here. Exact per-choice ranges and applicability are checked by make_values."""
    fields: dict = {}
    for option, (label, registry, default) in OPTIONS.items():
        names = tuple(registry)
        fields[option] = (Literal[names], Field(default, description=f"{label}: {', '.join(names)}",
                                                examples=[default]))
    for name, (label, registry, default, _, when) in SUB_OPTIONS.items():
        names = tuple(registry)
        fields[name] = (Optional[Literal[names]], Field(
            None, description=f"{label}: {', '.join(names)}; applies with {when}; default {default}"))
    for p in COMMON_PARAMS:
        if p.name in OPTIONAL_PARAMS:
            fields[p.name] = (Optional[float], Field(None, ge=p.lo, le=p.hi, description=p.description,
                                                     examples=[p.default]))
        else:
            fields[p.name] = (float, Field(p.default, ge=p.lo, le=p.hi, description=p.description,
                                           examples=[p.default]))
    for name, owners in choice_param_names().items():
        lo = min(p.lo for p in owners.values())
        hi = max(p.hi for p in owners.values())
        first = next(iter(owners.values()))
        where = " or ".join(owners)
        fields[name] = (Optional[float], Field(
            None, ge=lo, le=hi, examples=[first.default],
            description=f"{first.description} Applies with {where}; default {first.default:g}."))
    fields["material"] = (Optional[Annotated[str, AfterValidator(_material_slug)]], Field(
        None, examples=["gold"], description="a measured material (GET /api/v1/materials): sets fresnel to "
        "its kind with its RGB index; /eval then answers F_rgb and f_rgb beside the luminance F, f"))
    return fields


def _choice(option: str, name: str, entry) -> dict:
    out = {"name": name, "label": entry.label, "description": entry.description,
           "params": [p.as_dict() for p in choice_params(option, name)]}
    for attr in ("reference", "applies_to", "anisotropic", "isotropic_only", "needs_phi",
                 "approximation", "derived_doc"):
        if hasattr(entry, attr):
            out[attr] = getattr(entry, attr)
    return out


def catalogue() -> dict:
    """Every option with its choices and their parameters, the common parameters, the
    sub-options: what the page builds the microfacet controls from."""
    return {
        "params": [{**p.as_dict(), "optional": p.name in OPTIONAL_PARAMS} for p in COMMON_PARAMS],
        "options": {
            option: {"label": label, "default": default,
                     "choices": [_choice(option, name, entry) for name, entry in registry.items()]}
            for option, (label, registry, default) in OPTIONS.items()
        },
        "sub_options": {
            name: {"label": label, "default": default, "applies_with": when,
                   "choices": [{"name": key, "label": entry.label, "description": entry.description}
                               for key, entry in registry.items()]}
            for name, (label, registry, default, _, when) in SUB_OPTIONS.items()
        },
    }


def lobe_albedo(spec, mu) -> dict:
    """E(μ) of the model's two lobes: the diffuse term and the specular lobe (with its
    Kulla-Conty part); sheen and clearcoat 0 (the principled_albedo view's lobes)."""
    specular_brdf = spec.with_(kd=0.0).brdf()
    specular = albedo_by(specular_brdf, mu, average=False)
    E_d, E_d_error = spec.brdf().diffuse_albedo(mu)
    zero = {"E": np.zeros_like(mu), "E_error": 0.0, "E_avg": 0.0}
    lobes = {"diffuse": {"E": E_d, "E_error": E_d_error, "E_avg": spec.brdf().diffuse_albedo_avg()[0]},
             "specular": {"E": specular["E"], "E_error": float(np.max(specular["E_error"])),
                          "E_avg": float(albedo_by(specular_brdf, [1.0])["E_avg"])},
             "sheen": zero, "clearcoat": zero}
    return {"mu": mu, "E": E_d + specular["E"], "lobes": lobes, "channel": "luminance"}


FAMILY = Family(
    "microfacet", "Microfacet model",
    "A specular microfacet lobe built from your choice of NDF, masking, G2 and Fresnel, with a "
    "diffuse term.",
    "Walter et al. 2007; Heitz 2014; docs/conventions.md",
    make_values, brdf, as_query, query_fields, catalogue,
    albedo_methods=METHODS, lobe_albedo=lobe_albedo, edit=edit,
    display_names=lambda values: ({"material": materials.material(values["material"])["name"]}
                                  if values.get("material") else {}))
