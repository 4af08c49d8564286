"""What a figure's title and its export file name say about the model: every parameter
that differs from the defaults, so that two slides never share a title or a file name.

Names are written as names ("height-correlated", never an underscore a renderer could
turn into a subscript); symbols as the physics writes them (α, γ, F₀, η). The same list
of differences gives the title (``model_title``) and the file stem (``file_stem``).
"""
from __future__ import annotations

import re
from functools import lru_cache

from ..model import COMMON_PARAMS, OPTIONS, SUB_OPTIONS, choice_params, make_spec, principled_spec

#: Parameters shown with the roughness, not as separate differences.
_ROUGHNESS = ("alpha", "alpha_y", "roughness", "anisotropy", "aniso_map")
#: What an option is called in a title.
_OPTION_NAMES = {"masking": "Λ", "g2": "G2", "fresnel": "F", "multiscatter": "", "lambda_phi": "λ(φ)",
                 "aniso_map": "map"}


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
    for option in ("ndf", "fresnel"):
        for choice in OPTIONS[option][1]:
            for p in choice_params(option, choice):
                if p.name == name:
                    return p.label.split(" (")[0]
    return name


def differences(values: dict) -> list[tuple[str, object]]:
    """(name, value) of every model parameter that differs from the defaults, in the
    order of the model's options; ndf and α always (they identify the model)."""
    defaults = _defaults()
    out = [("ndf", values["ndf"])]
    out += [(p.name, values[p.name]) for p in choice_params("ndf", values["ndf"])]
    out += [(k, values.get(k)) for k in _ROUGHNESS if values.get(k) is not None]
    for option in ("masking", "g2", "lambda_phi", "fresnel", "multiscatter"):
        default = SUB_OPTIONS[option][2] if option in SUB_OPTIONS else defaults.get(option)
        if values.get(option) is not None and values.get(option) != default:
            out.append((option, values[option]))
    out += [(p.name, values[p.name]) for p in choice_params("fresnel", values["fresnel"])
            if values.get(p.name) is not None and (values["fresnel"] != defaults["fresnel"]
                                                    or values[p.name] != defaults.get(p.name))]
    for name in ("kd", "alpha2", "lobe_mix"):
        if values.get(name) is not None and values.get(name) != defaults.get(name):
            out.append((name, values[name]))
    return out


def _number(x) -> str:
    return f"{x:.4g}" if isinstance(x, float) else str(x)


def principled_differences(values: dict) -> list[tuple[str, object]]:
    """(name, value) of a principled model: the roughness always, then every parameter
    and option that differs from the paper's defaults (not the microfacet form it is
    built from, which is not what the user chose)."""
    defaults = _principled_defaults()
    out: list[tuple[str, object]] = [("roughness", values["roughness"])]
    if tuple(values["base_color"]) != tuple(defaults["base_color"]):
        out.append(("base_color", tuple(values["base_color"])))
    out += [(p.name, values[p.name]) for p in principled_spec.PARAMS if values[p.name] != defaults[p.name]]
    out += [(name, values[name]) for name, (_, _, default) in principled_spec.OPTIONS.items()
            if values[name] != default]
    return out


def principled_title(values: dict) -> str:
    """"Principled r=0.35 · base colour (0.2, 0.4, 0.6) · metallic=0.6 · Specular lobe"."""
    labels = {p.name: p.label for p in principled_spec.PARAMS}
    parts = []
    for name, value in principled_differences(values):
        if name == "roughness":
            parts.append(f"Principled r={_number(value)}")
        elif name == "base_color":
            parts.append("base colour (" + ", ".join(f"{c:.3g}" for c in value) + ")")
        elif name in labels:
            parts.append(f"{labels[name]}={_number(value)}")
        else:
            label = principled_spec.OPTIONS[name][1][value].label.split(" (")[0]
            parts.append(label + {"lobe": " lobe", "channel": " channel"}.get(name, ""))
    return " · ".join(parts)


@lru_cache(maxsize=1)
def _principled_defaults() -> dict:
    return dict(make_spec(model="principled").values)


def model_title(values: dict) -> str:
    """"GGX α=0.3"; "GTR γ=1.5 α=0.2 · G2 separable · F Dielectric η=1.33 · k_d=0.2":
    groups (the NDF, each option with its parameters, k_d, the second lobe) joined by ·."""
    if values.get("model") == "principled":
        return principled_title(values)
    groups: list[list[str]] = []
    for name, value in differences(values):
        if name in OPTIONS or name in SUB_OPTIONS:
            groups.append(option_text(name, value).split(" ", 1))
        elif name == "alpha_y":
            continue
        elif name == "alpha" and values.get("alpha_y") is not None:
            groups[-1].append(f"α=({_number(value)}, {_number(values['alpha_y'])})")
        elif name in ("kd", "alpha2"):
            groups.append([f"{_symbol(name)}={_number(value)}"])
        else:
            if name in {p.name for p in choice_params("fresnel", values["fresnel"])} \
                    and groups[-1][0] != "F":
                groups.append(["F", option_label("fresnel", values["fresnel"])])
            groups[-1].append(f"{_symbol(name)}={_number(value)}")
    text = " · ".join(" ".join(g) for g in groups)
    if "alpha_p" in values:
        text += f" (α_p={values['alpha_p']:.4g})"
    return text


def fresnel_text(values: dict) -> str:
    """The Fresnel form with every parameter it takes: "Schlick F₀=0.04 F₉₀=1 p=5"."""
    if values["fresnel"] == "none":
        return "none (F = 1)"
    params = [f"{_symbol(p.name)}={_number(values[p.name])}"
              for p in choice_params("fresnel", values["fresnel"]) if values.get(p.name) is not None]
    return " ".join([option_label("fresnel", values["fresnel"]), *params])


def file_stem(view: str, values: dict, view_values: dict | None = None,
              view_defaults: dict | None = None) -> str:
    """"lobe-ggx-alpha0.3-fresnel-dielectric-ior1.33-theta_i_deg45.5": the view, the
    model's differences and the view parameters that differ from ``view_defaults``
    (all given ones without it), safe for any file system."""
    parts = [view]
    principled = values.get("model") == "principled"
    for name, value in (principled_differences(values) if principled else differences(values)):
        if isinstance(value, tuple):
            value = "_".join(f"{c:g}" for c in value)
        parts.append(str(value) if name == "ndf" else f"{name}-{value}" if isinstance(value, str)
                     else f"{name}{_number(value)}")
    if principled:
        parts.insert(1, "principled")
    for name, value in (view_values or {}).items():
        if value is None or (view_defaults is not None and view_defaults.get(name) == value):
            continue
        parts.append(f"{name}{_number(value) if not isinstance(value, bool) else str(value).lower()}")
    return re.sub(r"[^A-Za-z0-9._-]", "_", "-".join(parts))
