"""What "roughness" means in each ecosystem: the microfacet α it gives, and the check for a
model whose D and G use different α.

Every entry computes α (and α_y with anisotropy) as that engine does, even outside the
range the explorer evaluates ([1e-4, 1]); the note says so.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, replace
from typing import Callable

import numpy as np

from ..integrate.albedo import albedo, albedo_average
from ..physics.masking import Masking
from ..physics.ndf import ALPHA

ALPHA_MIN, ALPHA_MAX = ALPHA.lo, ALPHA.hi
#: pbrt-v3 clamps roughness to this before its logarithm (TrowbridgeReitzDistribution::RoughnessToAlpha)
PBRT3_ROUGHNESS_MIN = 1e-3
#: Filament's smallest perceptual roughness (highp; mediump devices use 0.089): α ≥ 0.045²
FILAMENT_ROUGHNESS_MIN = 0.045


def _pbrt3(r: float) -> float:
    x = math.log(max(r, PBRT3_ROUGHNESS_MIN))
    return 1.62142 + 0.819955 * x + 0.1734 * x ** 2 + 0.0171201 * x ** 3 + 0.000640711 * x ** 4


def _burley(r: float, a: float) -> tuple[float, float]:
    aspect = math.sqrt(1.0 - 0.9 * a)
    return r * r / aspect, r * r * aspect


def _openpbr(r: float, a: float) -> tuple[float, float]:
    ax = r * r * math.sqrt(2.0 / (1.0 + (1.0 - a) ** 2))
    return ax, (1.0 - a) * ax


@dataclass(frozen=True)
class Convention:
    ecosystem: str
    alphas: Callable          # (r, anisotropy) -> (α_x, α_y)
    note: str
    k: Callable | None = None  # Schlick-GGX k for the G term, where the engine uses one


CONVENTIONS = [
    Convention("Disney (Burley 2012)", _burley,
               "α = r² (Burley 2012, sec. 5.4); anisotropic: aspect = √(1 − 0.9 k), α_x = r²/aspect, α_y = r² aspect."),
    Convention("glTF 2.0", lambda r, a: (r * r, r * r),
               "alphaRoughness = roughnessFactor² (glTF 2.0 spec, appendix B); isotropic in the core spec."),
    Convention("Filament", lambda r, a: (max(r, FILAMENT_ROUGHNESS_MIN) ** 2,) * 2,
               f"α = r², with r clamped to ≥ {FILAMENT_ROUGHNESS_MIN} (0.089 on mediump devices) to keep "
               "GGX's peak finite in half floats (Filament documentation, sec. 4.8)."),
    Convention("UE4, D (GGX)", lambda r, a: (r * r, r * r), "α = r² in D (Karis 2013, 'Real Shading in UE4')."),
    Convention("UE4, G direct light", lambda r, a: (r * r, r * r),
               "Schlick-GGX G1 = μ/(μ(1 − k) + k), k = (r + 1)²/8: 'remapped' roughness for analytic lights "
               "(Karis 2013); G does not use D's α.", k=lambda r: (r + 1.0) ** 2 / 8.0),
    Convention("UE4, G image-based light", lambda r, a: (r * r, r * r),
               "Schlick-GGX with k = r²/2 = α/2 (Karis 2013), as for the split-sum LUT.", k=lambda r: r * r / 2.0),
    Convention("pbrt-v3", lambda r, a: (_pbrt3(r),) * 2,
               "RoughnessToAlpha: x = ln(max(r, 1e-3)), α = 1.62142 + 0.819955x + 0.1734x² + 0.0171201x³ "
               "+ 0.000640711x⁴ (pbrt-v3, microfacet.h; used when remaproughness is true): its r is not "
               "perceptual roughness, r = 1 gives α ≈ 1.62."),
    Convention("pbrt-v4", lambda r, a: (math.sqrt(r),) * 2,
               "RoughnessToAlpha: α = √r (pbrt-v4, TrowbridgeReitzDistribution; with remaproughness true)."),
    Convention("Blender Principled (Burley map)", _burley,
               "α = r²; anisotropic k: aspect = √(1 − 0.9 k), α_x = r²/aspect, α_y = r² aspect (Blender's "
               "Principled BSDF after Burley 2012)."),
    Convention("OpenPBR Surface", _openpbr,
               "α = r²; anisotropy a: α_t = r² √(2/(1 + (1 − a)²)), α_b = (1 − a) α_t (OpenPBR Surface 1.0, "
               "specular anisotropy); at a = 0 both are r²."),
]


def table(roughness: float, anisotropy: float = 0.0) -> list[dict]:
    """[{"ecosystem", "alpha", "alpha_y", "note", ("k")}] for one roughness (and anisotropy)."""
    out = []
    for c in CONVENTIONS:
        ax, ay = c.alphas(roughness, anisotropy)
        notes = [c.note]
        for name, a in (("α", ax), ("α_y", ay)):
            if not ALPHA_MIN <= a <= ALPHA_MAX:
                notes.append(f"{name} = {a:.4g} is outside [{ALPHA_MIN:g}, {ALPHA_MAX:g}], the range the "
                             "explorer evaluates.")
        row = {"ecosystem": c.ecosystem, "alpha": ax, "alpha_y": ay, "note": " ".join(notes)}
        if c.k is not None:
            row["k"] = c.k(roughness)
        out.append(row)
    return out


def mismatched(brdf, alpha_G: float):
    """The BRDF with G (μΛ) evaluated at another isotropic α: the bug being checked."""
    other = type(brdf.ndf)(alpha_G, None, **{p.name: getattr(brdf.ndf, p.name) for p in brdf.ndf.shape_params})
    m = brdf.masking
    masking = Masking(f"{m.name}@alpha={alpha_G:g}", m.label, m.description,
                      lambda ndf, w: m.mu_Lambda(other, w))
    return replace(brdf, masking=masking)


def consistency(brdf, alpha_G: float, mu: np.ndarray, tol: float = 1e-5) -> dict:
    """E(μ) and E_avg with G at α_G against the consistent model (G at D's α)."""
    wrong = mismatched(brdf, alpha_G)
    right_E = albedo(brdf, mu, tol=tol)
    wrong_E = albedo(wrong, mu, tol=tol)
    right_avg, right_err, _ = albedo_average(brdf, tol=tol)
    wrong_avg, wrong_err, _ = albedo_average(wrong, tol=tol)
    diff = wrong_E.E - right_E.E
    return {"alpha_D": brdf.ndf.alpha_x, "alpha_G": alpha_G, "consistent": alpha_G == brdf.ndf.alpha_x,
            "mu": mu, "E_consistent": right_E.E, "E_mismatched": wrong_E.E, "E_difference": diff,
            "E_error": right_E.E_error + wrong_E.E_error,
            "E_avg_consistent": right_avg, "E_avg_mismatched": wrong_avg,
            "E_avg_difference": wrong_avg - right_avg, "E_avg_error": right_err + wrong_err,
            "max_E_difference": float(np.max(np.abs(diff)))}
