"""What a figure's title and its export file name say about the model: every parameter
that differs from the defaults, so that two slides never share a title or a file name.

Names are written as names ("height-correlated", never an underscore a renderer could
turn into a subscript); symbols as the physics writes them (α, γ, F₀, η). The same list
of differences gives the title (``model_title``) and the file stem (``file_stem``). Each
model family may write its own (``Family.title``/``differences``: the microfacet form is
here, :func:`microfacet_title`; the principled one in app/principled/title.py); a family
without them is written generically from its own query.
"""
from __future__ import annotations

import re
from functools import lru_cache

from ..model.microfacet import COMMON_PARAMS, OPTIONS, SUB_OPTIONS, choice_params
from ..model.registry import DEFAULT, family_of, make_spec

#: Parameters shown with the roughness, not as separate differences.
_ROUGHNESS = ("alpha", "alpha_y", "roughness", "anisotropy", "aniso_map")
#: What an option is called in a title.
_OPTION_NAMES = {"masking": "Λ", "g2": "G2", "fresnel": "F", "multiscatter": "", "lambda_phi": "λ(φ)",
                 "aniso_map": "map", "diffuse": "diffuse"}


@lru_cache(maxsize=1)
def _defaults() -> dict:
    return dict(make_spec().values)


def option_label(option: str, name: str) -> str:
    """The choice's own label without its parenthesis: "GTR", "Height-correlated"."""
    registry = OPTIONS[option][1] if option in OPTIONS else SUB_OPTIONS[option][1]
    label = getattr(registry[name], "label", name)
    return label.split(" (")[0].strip() or name.replace("_", "-")


def option_text(option: str, name: str) -> str:
    """A choice as a title writes it: "GGX", "Λ Walter", "G2 separable", "F = 1"."""
    if option == "fresnel" and name == "none":
        return "F = 1"
    label = option_label(option, name)
    prefix = "" if option == "ndf" else _OPTION_NAMES.get(option, option)
    return f"{prefix} {label.lower() if option == 'g2' else label}" if prefix else label


def _symbol(name: str) -> str:
    if name == "anisotropy":
        return "k"
    for p in COMMON_PARAMS:
        if p.name == name:
            return p.label.split(" (")[0]
    for option in ("ndf", "fresnel", "diffuse"):
        for choice in OPTIONS[option][1]:
            for p in choice_params(option, choice):
                if p.name == name:
                    return p.label.split(" (")[0]
    return name


def differences(values: dict) -> list[tuple[str, object]]:
    """(name, value) of every microfacet parameter that differs from the defaults, in the
    order of the model's options; ndf and α always (they identify the model); a measured
    material in place of the Fresnel form it sets; the diffuse model and its parameters."""
    defaults = _defaults()
    out = [("ndf", values["ndf"])]
    out += [(p.name, values[p.name]) for p in choice_params("ndf", values["ndf"])]
    out += [(k, values.get(k)) for k in _ROUGHNESS if values.get(k) is not None]
    for option in ("masking", "g2", "lambda_phi", "fresnel", "multiscatter"):
        default = SUB_OPTIONS[option][2] if option in SUB_OPTIONS else defaults.get(option)
        if option == "fresnel" and values.get("material"):
            out.append(("material", values["material"]))
        elif values.get(option) is not None and values.get(option) != default:
            out.append((option, values[option]))
    out += [(p.name, values[p.name]) for p in choice_params("fresnel", values["fresnel"])
            if values.get(p.name) is not None and (values["fresnel"] != defaults["fresnel"]
                                                    or values[p.name] != defaults.get(p.name))]
    if values.get("diffuse", defaults["diffuse"]) != defaults["diffuse"]:
        out.append(("diffuse", values["diffuse"]))
        out += [(p.name, values[p.name]) for p in choice_params("diffuse", values["diffuse"])
                if values.get(p.name) is not None]
    for name in ("kd", "alpha2", "lobe_mix"):
        if values.get(name) is not None and values.get(name) != defaults.get(name):
            out.append((name, values[name]))
    return out


def number(x) -> str:
    return f"{x:.4g}" if isinstance(x, float) else str(x)


def generic_differences(family, values: dict) -> list[tuple[str, object]]:
    """(name, value) of a family without its own form: every parameter of its query that
    differs from the family's defaults."""
    defaults = family.as_query(family.make_values({}))
    return [(k, v) for k, v in family.as_query(values).items()
            if k != "model" and v != defaults.get(k)]


def generic_title(family, values: dict) -> str:
    """"Lambert + Phong · k_s=0.3": the family's label, then what differs, by label."""
    labels = {p["name"]: p["label"].split(" (")[0] for p in family.catalogue().get("params", [])}
    return " · ".join([family.label.split(" (")[0]] + [
        f"{labels.get(k, k)}={number(v)}" for k, v in generic_differences(family, values)])


def model_title(values: dict) -> str:
    """The model as its family writes it; the default (microfacet) family's form is
    :func:`microfacet_title`; a family without one, :func:`generic_title`."""
    family = family_of(values)
    if family.title:
        return family.title(values)
    if family.name == DEFAULT:
        return microfacet_title(values, family.display_names(values).get("material"))
    return generic_title(family, values)


def _differences(family, values: dict) -> list[tuple[str, object]]:
    if family.differences:
        return family.differences(values)
    return differences(values) if family.name == DEFAULT else generic_differences(family, values)


def microfacet_title(values: dict, material_name: str | None = None) -> str:
    """"GGX α=0.3"; "GTR γ=1.5 α=0.2 · G2 separable · F Dielectric η=1.33 · k_d=0.2":
    groups (the NDF, each option with its parameters, the material — ``material_name``,
    passed in by the family, which knows the materials —, the diffuse model, k_d, the
    second lobe) joined by ·: "GGX α=0.3 · F Gold · diffuse Burley · k_d=0.5"."""
    groups: list[list[str]] = []
    for name, value in differences(values):
        if name in OPTIONS or name in SUB_OPTIONS:
            groups.append(option_text(name, value).split(" ", 1))
        elif name == "alpha_y":
            continue
        elif name == "alpha" and values.get("alpha_y") is not None:
            groups[-1].append(f"α=({number(value)}, {number(values['alpha_y'])})")
        elif name == "material":
            groups.append(["F", material_name or value])
        elif name in ("kd", "alpha2"):
            groups.append([f"{_symbol(name)}={number(value)}"])
        elif name in {p.name for p in choice_params("diffuse", values.get("diffuse", _defaults()["diffuse"]))}:
            groups[-1].append(f"{_symbol(name)}={number(value)}")
        else:
            if name in {p.name for p in choice_params("fresnel", values["fresnel"])} \
                    and groups[-1][0] != "F":
                groups.append(["F", option_label("fresnel", values["fresnel"])])
            groups[-1].append(f"{_symbol(name)}={number(value)}")
    text = " · ".join(" ".join(g) for g in groups)
    if "alpha_p" in values:
        text += f" (α_p={values['alpha_p']:.4g})"
    return text


def fresnel_text(values: dict) -> str:
    """The Fresnel form with every parameter it takes: "Schlick F₀=0.04 F₉₀=1 p=5"; a
    measured material's name where one sets it: "Gold (measured)"."""
    if values.get("material"):
        name = family_of(values).display_names(values).get("material") or values["material"]
        return f"{name} (measured)"
    if values["fresnel"] == "none":
        return "none (F = 1)"
    params = [f"{_symbol(p.name)}={number(values[p.name])}"
              for p in choice_params("fresnel", values["fresnel"]) if values.get(p.name) is not None]
    return " ".join([option_label("fresnel", values["fresnel"]), *params])


def file_stem(view: str, values: dict, view_values: dict | None = None,
              view_defaults: dict | None = None) -> str:
    """"lobe-ggx-alpha0.3-fresnel-dielectric-ior1.33-theta_i_deg45.5": the view, the
    model's differences and the view parameters that differ from ``view_defaults``
    (all given ones without it), safe for any file system."""
    parts = [view]
    family = family_of(values)
    for name, value in _differences(family, values):
        if isinstance(value, tuple):
            value = "_".join(f"{c:g}" for c in value)
        parts.append(str(value) if name == "ndf" else f"{name}-{value}" if isinstance(value, str)
                     else f"{name}{number(value)}")
    if family.name != DEFAULT:
        parts.insert(1, family.name)
    for name, value in (view_values or {}).items():
        if value is None or (view_defaults is not None and view_defaults.get(name) == value):
            continue
        parts.append(f"{name}{number(value) if not isinstance(value, bool) else str(value).lower()}")
    return re.sub(r"[^A-Za-z0-9._-]", "_", "-".join(parts))
