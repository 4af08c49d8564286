"""The principled model in a figure title and a file name: what the user chose (the
paper's parameters and options), not the microfacet form it is built from."""
from __future__ import annotations

from functools import lru_cache

from ..figures.titles import number
from . import spec
from .params import OPTIONS, PARAMS


@lru_cache(maxsize=1)
def _defaults() -> dict:
    return spec.make_values({})


def differences(values: dict) -> list[tuple[str, object]]:
    """(name, value): the roughness always, then every parameter and option that differs
    from the paper's defaults."""
    defaults = _defaults()
    out: list[tuple[str, object]] = [("roughness", values["roughness"])]
    if tuple(values["base_color"]) != tuple(defaults["base_color"]):
        out.append(("base_color", tuple(values["base_color"])))
    out += [(p.name, values[p.name]) for p in PARAMS if values[p.name] != defaults[p.name]]
    out += [(name, values[name]) for name, (_, _, default) in OPTIONS.items() if values[name] != default]
    return out


def title(values: dict) -> str:
    """"Principled r=0.35 · base colour (0.2, 0.4, 0.6) · metallic=0.6 · EON · Specular lobe":
    the diffuse model is named whenever it is not the paper's."""
    labels = {p.name: p.label for p in PARAMS}
    parts = []
    for name, value in differences(values):
        if name == "roughness":
            parts.append(f"Principled r={number(value)}")
        elif name == "base_color":
            parts.append("base colour (" + ", ".join(f"{c:.3g}" for c in value) + ")")
        elif name in labels:
            parts.append(f"{labels[name]}={number(value)}")
        else:
            label = OPTIONS[name][1][value].label.split(" (")[0]
            parts.append(label + {"lobe": " lobe", "channel": " channel",
                                  "principled_diffuse": " diffuse"}.get(name, ""))
    return " · ".join(parts)
