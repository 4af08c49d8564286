"""The principled BRDF's parameters (Burley 2012, sec. 5.2 and the BRDF Explorer's
``disney.brdf``): every one in [0, 1], defaults those of ``disney.brdf``, and the
options where implementations differ (docs/principled.md), each defaulting to the paper.
"""
from __future__ import annotations

from dataclasses import dataclass

from ..physics.params import Param


def _p(name, label, default, description):
    return Param(name, label, 0.0, 1.0, default, description)


#: base_color is given as "r,g,b" (three numbers in [0, 1]); its default is disney.brdf's.
BASE_COLOR_DEFAULT = (0.82, 0.67, 0.16)

PARAMS: tuple[Param, ...] = (
    _p("metallic", "metallic", 0.0, "0 = dielectric (diffuse + white specular), 1 = metal "
       "(specular tinted by the base colour, no diffuse)."),
    _p("specular", "specular", 0.5, "Incident specular amount: F₀ = 0.08·specular "
       "(0.5 ↔ F₀ = 0.04, η ≈ 1.5)."),
    _p("specular_tint", "specular tint", 0.0, "Tints the dielectric F₀ toward the base colour's hue."),
    _p("anisotropic", "anisotropic", 0.0, "Aspect √(1 − 0.9·anisotropic): α_x = r²/aspect, α_y = r²·aspect."),
    _p("sheen", "sheen", 0.0, "Grazing retro-reflective sheen (cloth): sheen·(1 − cos θ_d)⁵."),
    _p("sheen_tint", "sheen tint", 0.5, "Tints the sheen toward the base colour's hue."),
    _p("clearcoat", "clearcoat", 0.0, "A second, colourless specular lobe (GTR1, F₀ = 0.04) "
       "weighted 0.25·clearcoat."),
    _p("clearcoat_gloss", "clearcoat gloss", 1.0, "GTR1 α = 0.1 (satin, gloss 0) … 0.001 (gloss, 1)."),
    _p("subsurface", "subsurface", 0.0, "Blends Burley's diffuse toward the Hanrahan–Krueger-like "
       "subsurface lobe (flatter, darker at grazing, brighter at the rim)."),
)
NAMES = tuple(p.name for p in PARAMS)


@dataclass(frozen=True)
class Choice:
    name: str
    label: str
    description: str


def _choices(*items):
    return {c.name: c for c in (Choice(*i) for i in items)}


#: Where implementations differ, as options (name → (label, choices, default)).
OPTIONS = {
    "principled_g2": ("Principled specular G2", _choices(
        ("separable", "Separable Smith (Burley 2012)", "G1(l) G1(v), as disney.brdf."),
        ("height_correlated", "Height-correlated Smith (Blender, glTF, OpenPBR)",
         "1/(1 + Λ(l) + Λ(v)): brighter at grazing, what most renderers use now.")), "separable"),
    "principled_diffuse": ("Principled diffuse", _choices(
        ("burley", "Burley (Burley 2012)", "Retro-reflective diffuse with the subsurface blend."),
        ("lambert", "Lambert (glTF core)", "base colour/π; subsurface blends toward the same lobe."),
        ("eon", "EON (OpenPBR)", "Energy-preserving Oren–Nayar with r = roughness.")), "burley"),
    "principled_multiscatter": ("Principled specular multiple scattering", _choices(
        ("none", "None (Burley 2012)", "Single scattering: rough metals lose energy."),
        ("kulla_conty", "Kulla-Conty (Blender multiscatter GGX, OpenPBR)",
         "Adds the per-channel Kulla-Conty lobe; isotropic roughness only.")), "none"),
    "base_color_space": ("Base colour encoding", _choices(
        ("linear", "Linear", "base_color is linear reflectance."),
        ("srgb", "sRGB-like (disney.brdf's pow 2.2)", "base_color is decoded with x^2.2 first.")), "linear"),
    "lobe": ("Lobe shown", _choices(
        ("all", "All lobes", "f = diffuse + sheen + specular + clearcoat."),
        ("diffuse", "Diffuse", "(1 − metallic)·base colour·mix(F_d, subsurface)/π."),
        ("sheen", "Sheen", "(1 − metallic)·sheen·C_sheen·(1 − cos θ_d)⁵."),
        ("specular", "Specular", "GTR2 (GGX) with Schlick F from C_spec0."),
        ("clearcoat", "Clearcoat", "0.25·clearcoat·GTR1 with Smith GGX (α = 0.25) and F₀ = 0.04.")), "all"),
    "channel": ("Channel drawn", _choices(
        ("luminance", "Luminance", "Rec. 709 luminance Y = 0.2126 R + 0.7152 G + 0.0722 B."),
        ("r", "Red", "The red channel."), ("g", "Green", "The green channel."),
        ("b", "Blue", "The blue channel.")), "luminance"),
}

LOBES = ("diffuse", "sheen", "specular", "clearcoat")
#: Rec. 709 / sRGB luminance weights.
LUMINANCE = (0.2126, 0.7152, 0.0722)
