"""The principled material: colours derived once from the parameters, its registry
parts (GGX specular, GTR1 clearcoat NDF, per-channel Kulla-Conty), and f per lobe and
channel; :class:`PrincipledBRDF` lets every view evaluate it like any BRDF.

Colour (Burley 2012, appendix): C_tint = C/lum(C) (lum = 0.3 R + 0.6 G + 0.1 B, as
disney.brdf), C_spec0 = mix(0.08·specular·mix(1, C_tint, specular_tint), C, metallic),
C_sheen = mix(1, C_tint, sheen_tint). Roughness: α = max(0.001, r²/aspect) along t,
max(0.001, r²·aspect) along b, aspect = √(1 − 0.9·anisotropic).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from functools import cached_property
from typing import ClassVar

import numpy as np

from ..integrate.compensation import kulla_conty
from ..physics.brdf import BRDF
from ..physics.fresnel import FRESNELS
from ..physics.g2 import G2_FORMS
from ..physics.masking import MASKINGS
from ..physics.ndf import NDFS
from . import lobes as lobe_formulas
from .albedo import rest_albedo
from .colour import channel
from .params import LOBES, LUMINANCE

#: disney.brdf's floor on α (the paper's "max(.001, …)"): GGX at α → 0 is a delta.
ALPHA_MIN = 0.001
#: disney.brdf's gamma for base_color_space=srgb (mon2lin: x^2.2).
GAMMA = 2.2
#: The lobes that take the shared Schlick weight (1 − cos θ_d)⁵ as ``w``.
SHARE_W = {"sheen", "specular", "clearcoat"}


@dataclass(frozen=True, eq=False)
class Principled:
    base_color: tuple = (0.82, 0.67, 0.16)
    metallic: float = 0.0
    specular: float = 0.5
    specular_tint: float = 0.0
    roughness: float = 0.5
    anisotropic: float = 0.0
    sheen: float = 0.0
    sheen_tint: float = 0.5
    clearcoat: float = 0.0
    clearcoat_gloss: float = 1.0
    subsurface: float = 0.0
    options: dict = field(default_factory=lambda: {
        "principled_g2": "separable", "principled_diffuse": "burley",
        "principled_multiscatter": "none", "base_color_space": "linear"})

    @cached_property
    def base_linear(self) -> np.ndarray:
        c = np.asarray(self.base_color, dtype=float)
        return c ** GAMMA if self.options.get("base_color_space") == "srgb" else c

    @cached_property
    def tint(self) -> np.ndarray:
        lum = float(np.dot([0.3, 0.6, 0.1], self.base_linear))
        return self.base_linear / lum if lum > 0 else np.ones(3)

    @cached_property
    def specular_color(self) -> np.ndarray:
        dielectric = 0.08 * self.specular * ((1 - self.specular_tint) + self.specular_tint * self.tint)
        return (1 - self.metallic) * dielectric + self.metallic * self.base_linear

    @cached_property
    def sheen_color(self) -> np.ndarray:
        return (1 - self.sheen_tint) + self.sheen_tint * self.tint

    @cached_property
    def alphas(self) -> tuple[float, float]:
        aspect = float(np.sqrt(1.0 - 0.9 * self.anisotropic))
        r2 = self.roughness ** 2
        return max(ALPHA_MIN, r2 / aspect), max(ALPHA_MIN, r2 * aspect)

    def specular_brdf(self, fresnel) -> BRDF:
        ax, ay = self.alphas
        return BRDF(NDFS["ggx"](ax, None if ax == ay else ay), MASKINGS["smith"],
                    G2_FORMS[self.options["principled_g2"]], fresnel)

    def clearcoat_ndf(self):
        """GTR1 (the registry's GTR at γ = 1), α = mix(0.1, 0.001, clearcoat_gloss)."""
        return NDFS["gtr"](0.1 + (0.001 - 0.1) * self.clearcoat_gloss, None, gamma=1.0)

    def multiscatter(self) -> list:
        """Per channel, the Kulla-Conty lobe of the GGX with F = Schlick(C_spec0, 1)."""
        if "_ms" not in self.__dict__:
            self.__dict__["_ms"] = [kulla_conty(self.specular_brdf(FRESNELS["schlick"](f0=float(c))))
                                    for c in self.specular_color]
        return self.__dict__["_ms"]

    def evaluate(self, l, v, lobes=LOBES) -> dict[str, np.ndarray]:
        """f of each lobe, (..., 3), for local directions; 0 unless both are upper."""
        l, v = np.broadcast_arrays(np.asarray(l, dtype=float), np.asarray(v, dtype=float))
        upper = (l[..., 2] >= 0) & (v[..., 2] >= 0)
        if upper.all():                 # (the renderer's samples) no masked copies
            w = lobe_formulas.theta_d_weight(l, v) if set(lobes) & SHARE_W else None
            return {name: (np.zeros(l.shape[:-1] + (3,)) if self.is_zero(name) else
                           lobe_formulas.LOBE_FUNCTIONS[name](self, l, v, **({"w": w} if name in SHARE_W else {})))
                    for name in lobes}
        out = {}
        for name in lobes:
            value = np.zeros(l.shape[:-1] + (3,))
            if upper.any() and not self.is_zero(name):
                value[upper] = lobe_formulas.LOBE_FUNCTIONS[name](self, l[upper], v[upper])
            out[name] = value
        return out

    def is_zero(self, lobe: str) -> bool:
        """Whether a lobe's colour (or weight) is 0, so that its f is 0 everywhere."""
        if lobe == "diffuse":
            return not ((1.0 - self.metallic) * self.base_linear).any()
        if lobe == "sheen":
            return not ((1.0 - self.metallic) * self.sheen * self.sheen_color).any()
        return lobe == "clearcoat" and self.clearcoat == 0

    def f_rgb(self, l, v, lobe: str = "all") -> np.ndarray:
        parts = iter(self.evaluate(l, v, LOBES if lobe == "all" else (lobe,)).values())
        total = next(parts)
        for part in parts:
            total += part
        return total


@dataclass(frozen=True)
class PrincipledBRDF(BRDF):
    """The principled material as a BRDF: ``f`` is the chosen lobe(s) in the chosen
    channel, ``f_rgb`` all three channels, ``f_diffuse`` the diffuse + sheen lobes; D,
    G1, G2 and F are the specular lobe's (F of the luminance of C_spec0)."""
    material: Principled | None = None
    lobe: str = "all"
    channel: str = "luminance"
    #: Not one of the compiled loops' models (app/kernels takes the numpy path).
    numpy_only: ClassVar[bool] = True

    def evaluate(self, l, v, want=("f",)) -> dict[str, np.ndarray]:
        l = np.asarray(l, dtype=float)
        v = np.asarray(v, dtype=float)
        terms = tuple(q for q in want if q not in ("f", "f_rgb", "f_diffuse"))
        out = BRDF.evaluate(self, l, v, terms) if terms else {}
        if "f" in want or "f_rgb" in want:
            rgb = self.material.f_rgb(l, v, self.lobe)
            if "f_rgb" in want:
                out["f_rgb"] = rgb
            if "f" in want:
                out["f"] = channel(rgb, self.channel)
        if "f_diffuse" in want:
            parts = self.material.evaluate(l, v, ("diffuse", "sheen"))
            out["f_diffuse"] = channel(parts["diffuse"] + parts["sheen"], self.channel)
        return out

    def lobes(self):
        """[(weight, microfacet BRDF)]: the specular lobe in the drawn channel as what the
        albedo quadrature integrates (integrate/albedo.py, adaptive in its own GGX). E is
        linear in F and F_c = C_spec0,c + (1 − C_spec0,c)(1 − cos θ_d)⁵, so the lobe is
        w·(F = 1) + (1 − w)·(F = (1 − cos θ_d)⁵) with w = C_spec0 in the channel (the
        luminance's weights sum to 1); weight 0 when the specular lobe is not drawn."""
        w = float(channel(self.material.specular_color, self.channel))
        shown = self.lobe in ("all", "specular")
        return [(w if shown else 0.0, self.material.specular_brdf(FRESNELS["none"]())),
                (1.0 - w if shown else 0.0, self.material.specular_brdf(FRESNELS["schlick"](f0=0.0, f90=1.0)))]

    def diffuse_albedo(self, mu) -> tuple[np.ndarray, float]:
        """(E(μ), its error) of what :meth:`lobes` leaves out, in the drawn channel: the
        diffuse, sheen and clearcoat lobes by their own rules and the specular lobe's
        Kulla-Conty part, exact (app/principled/albedo.py)."""
        return rest_albedo(self, mu)


def principled_brdf(material: Principled, lobe: str = "all", channel_name: str = "luminance") -> PrincipledBRDF:
    lum_c0 = float(np.dot(LUMINANCE, material.specular_color))
    spec = material.specular_brdf(FRESNELS["schlick"](f0=min(max(lum_c0, 0.0), 1.0)))
    return PrincipledBRDF(spec.ndf, spec.masking, spec.g2, spec.fresnel, material=material,
                          lobe=lobe, channel=channel_name)
