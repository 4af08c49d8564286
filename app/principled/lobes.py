"""The principled BRDF's lobes for direction pairs, per RGB channel (Burley 2012, sec. 5
and appendix; the BRDF Explorer's ``disney.brdf``), each returning (..., 3).

All four take local directions (n = +z) in the upper hemisphere; h = (l + v)/‖l + v‖ and
cos θ_d = l·h = √((1 + l·v)/2). The specular lobe is the registry's GGX with Smith
masking (no Fresnel: D·V), times the per-channel Schlick F; the clearcoat lobe is the
registry's GTR (γ = 1) with Smith masking of a GGX of fixed α = 0.25, as the paper fixes it.
"""
from __future__ import annotations

import numpy as np

from .. import kernels
from ..physics.diffuse import DIFFUSES
from ..physics.diffuse.base import schlick_weight, schlick_weight_body, times_rho
from ..physics.formula import Formula
from ..physics.fresnel import FRESNELS
from ..physics.masking import MASKINGS
from ..physics.ndf import NDFS
from ..physics.numeric import where_valid
from ..physics.vectors import dot
from ..integrate.compensation import MIN_ENERGY_LOSS
from .compensation import f_ms_rgb

#: The clearcoat's masking roughness, fixed by the paper ("α_g = 0.25").
CLEARCOAT_MASKING_ALPHA = 0.25
#: The clearcoat's F₀ (η = 1.5).
CLEARCOAT_F0 = 0.04


def cos_theta_d(l_dot_v) -> np.ndarray:
    return np.sqrt(np.clip(0.5 * (1.0 + np.asarray(l_dot_v, dtype=float)), 0.0, 1.0))


def subsurface(roughness: float, mu_l, mu_v, l_dot_v) -> np.ndarray:
    """Burley's Hanrahan–Krueger-like lobe /π: 1.25 (F_ss (1/(μ_l + μ_v) − 0.5) + 0.5)/π,
    F_ss = (1 + (F_ss90 − 1)(1 − μ_l)⁵)(1 + (F_ss90 − 1)(1 − μ_v)⁵), F_ss90 = r cos²θ_d.
    +inf where both directions lie on the horizon (its limit)."""
    f90 = roughness * 0.5 * (1.0 + np.asarray(l_dot_v, dtype=float))
    f_ss = (1.0 + (f90 - 1.0) * schlick_weight(mu_l)) * (1.0 + (f90 - 1.0) * schlick_weight(mu_v))
    inv = where_valid(np.asarray(mu_l) + np.asarray(mu_v) > 0, [np.asarray(mu_l) + mu_v],
                      lambda s: 1.0 / s, np.inf)
    return 1.25 * (f_ss * (inv - 0.5) + 0.5) / np.pi


#: principled_diffuse → (the registry's diffuse model, its values at the principled
#: roughness r, its formula's p as expressions of r: what generated code passes when r is
#: a uniform). Burley's p is its perceptual roughness √α = r; EON's r is the roughness.
DIFFUSE_CHOICES = {
    "burley": ("burley", lambda r: {"alpha": r * r}, ("r",)),
    "eon": ("eon", lambda r: {"diffuse_roughness": r}, ("r",)),
    "lambert": ("lambert", lambda r: {}, ()),
}


def diffuse_model(material):
    """The registry's diffuse model the option names, at the material's roughness."""
    name, values, _ = DIFFUSE_CHOICES[material.options["principled_diffuse"]]
    return DIFFUSES[name](**values(material.roughness))


def diffuse_rho(material, rho: float, mu_l, mu_v, l_dot_v) -> np.ndarray:
    """mix(f_d(ρ), ρ·ss, subsurface) for one channel's albedo ρ = (1 − metallic)·C: ρ
    goes inside the diffuse model, which need not be linear in it (EON's multiple-
    scattering albedo ρ_ms = ρ² E_F,avg/(1 − ρ(1 − E_F,avg)), Portsmouth et al. 2025)."""
    base = np.asarray(diffuse_model(material).f(rho, mu_l, mu_v, l_dot_v), dtype=float)
    if material.subsurface == 0:
        return base
    ss = subsurface(material.roughness, mu_l, mu_v, l_dot_v)
    return (1.0 - material.subsurface) * base + material.subsurface * times_rho(rho, ss)


def diffuse(material, l, v) -> np.ndarray:
    """The diffuse lobe per channel, each channel's colour inside its model."""
    colour = (1.0 - material.metallic) * material.base_linear
    if not colour.any():
        return np.zeros(np.shape(l)[:-1] + (3,))
    mu_l, mu_v, l_dot_v = l[..., 2], v[..., 2], dot(l, v)
    return np.stack([diffuse_rho(material, float(c), mu_l, mu_v, l_dot_v) for c in colour], axis=-1)


def theta_d_weight(l, v) -> np.ndarray:
    """(1 − cos θ_d)⁵: the Schlick weight the sheen, specular and clearcoat lobes share
    (:meth:`Principled.f_rgb` computes it once and passes it as ``w``)."""
    return schlick_weight(cos_theta_d(dot(l, v)))


def sheen(material, l, v, w=None) -> np.ndarray:
    """(1 − metallic)·sheen·C_sheen·(1 − cos θ_d)⁵ (no 1/π: as the paper writes it)."""
    colour = (1.0 - material.metallic) * material.sheen * material.sheen_color
    return (theta_d_weight(l, v) if w is None else w)[..., None] * colour


def specular_DV(material, l, v) -> np.ndarray:
    """D(h) G2/(4 μ_l μ_v) of the GGX lobe (F = 1), from the registry's BRDF: its
    compiled loop when ready (app/kernels, the same formulas), else numpy."""
    l, v = np.broadcast_arrays(np.asarray(l, dtype=float), np.asarray(v, dtype=float))
    f = kernels.f(material.specular_brdf(FRESNELS["none"]()), l.reshape(-1, 3), v.reshape(-1, 3))
    return f.reshape(l.shape[:-1])


def specular(material, l, v, w=None) -> np.ndarray:
    """D·V·F_c with F_c = C_spec0 + (1 − C_spec0)(1 − cos θ_d)⁵ per channel, plus the
    per-channel Kulla-Conty lobe with that option."""
    w = (theta_d_weight(l, v) if w is None else w)[..., None]
    c0 = material.specular_color
    out = specular_DV(material, l, v)[..., None] * (c0 + (1.0 - c0) * w)
    if material.options["principled_multiscatter"] == "kulla_conty":
        out = out + f_ms_rgb(material.multiscatter(), l[..., 2], v[..., 2])
    return out


def clearcoat(material, l, v, w=None) -> np.ndarray:
    """0.25·clearcoat·D_GTR1(h) F(cos θ_d) G1(l) G1(v)/(4 μ_l μ_v), F₀ = 0.04, G1 of a GGX
    with α = 0.25; G1/μ = 1/(μ + μΛ) is finite at μ = 0."""
    if material.clearcoat == 0:
        return np.zeros(np.shape(l)[:-1] + (3,))
    lv = l + v
    norm = np.sqrt(np.einsum("...i,...i->...", lv, lv))[..., None]
    exists = norm[..., 0] > 0
    if exists.all():                # h exists unless l = −v (both on the horizon)
        D = material.clearcoat_ndf().D(lv / norm)
    else:
        h = where_valid(exists[..., None], [lv, norm], lambda a, b: a / b, 0.0)
        D = np.where(exists, material.clearcoat_ndf().D(np.where(exists[..., None], h, [0.0, 0.0, 1.0])), 0.0)
    mask = MASKINGS["smith"]
    ggx = NDFS["ggx"](CLEARCOAT_MASKING_ALPHA, None)
    v_term = 0.25 / ((l[..., 2] + mask.mu_Lambda(ggx, l)) * (v[..., 2] + mask.mu_Lambda(ggx, v)))
    F = CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) * (theta_d_weight(l, v) if w is None else w)
    return (0.25 * material.clearcoat * D * F * v_term)[..., None] * np.ones(3)


LOBE_FUNCTIONS = {"diffuse": diffuse, "sheen": sheen, "specular": specular, "clearcoat": clearcoat}


# The same lobes written once in the expression language (app/physics/formula.py) for
# generated code (app/shader/principled.py); each beside the registry's own formulas it
# is combined with (GGX, Smith, the G2 forms, Schlick, GTR, the diffuse models). The
# numpy functions above stay the reference these are tested against.
PI_CONST = (("PI", np.pi, "π"),)

#: Burley 2012 (appendix; disney.brdf): lum = 0.3 R + 0.6 G + 0.1 B, C_tint = C/lum.
TINT_FORMULA = Formula("principled_tint", ("c", "lum"), "sel(lum > 0.0, c / lum, 1.0)",
                       doc="C_tint = C/lum(C), 1 where lum = 0 (Burley 2012, appendix).")
#: C_spec0 = mix(0.08 specular mix(1, C_tint, specular_tint), C, metallic).
SPEC0_FORMULA = Formula(
    "principled_spec0", ("c", "tint"),
    "(1.0 - metallic) * 0.08 * specular * ((1.0 - specular_tint) + specular_tint * tint) + metallic * c",
    p=("metallic", "specular", "specular_tint"),
    doc="C_spec0 = mix(0.08 specular mix(1, C_tint, specular_tint), C, metallic) (Burley 2012, appendix).")
#: C_sheen = mix(1, C_tint, sheen_tint).
SHEEN_COLOR_FORMULA = Formula("principled_sheen_color", ("tint",), "(1.0 - sheen_tint) + sheen_tint * tint",
                              p=("sheen_tint",), doc="C_sheen = mix(1, C_tint, sheen_tint) (Burley 2012, appendix).")
#: α along t and b: max(ALPHA_MIN, r²/aspect), max(ALPHA_MIN, r² aspect), aspect = √(1 − 0.9 anisotropic).
ALPHA_X_FORMULA = Formula("principled_alpha_x", ("roughness", "anisotropic"),
                          "max(ALPHA_MIN, roughness * roughness / sqrt(1.0 - 0.9 * anisotropic))",
                          consts=(("ALPHA_MIN", 0.001, "disney.brdf's floor on α"),),
                          doc="α_x = max(0.001, r²/aspect), aspect = √(1 − 0.9 anisotropic) (Burley 2012, appendix).")
ALPHA_Y_FORMULA = Formula("principled_alpha_y", ("roughness", "anisotropic"),
                          "max(ALPHA_MIN, roughness * roughness * sqrt(1.0 - 0.9 * anisotropic))",
                          consts=(("ALPHA_MIN", 0.001, "disney.brdf's floor on α"),),
                          doc="α_y = max(0.001, r² aspect) (Burley 2012, appendix).")
#: The clearcoat's GTR1 α = mix(0.1, 0.001, clearcoat_gloss).
CLEARCOAT_ALPHA_FORMULA = Formula("principled_clearcoat_alpha", ("gloss",), "0.1 + (0.001 - 0.1) * gloss",
                                  doc="Clearcoat α = mix(0.1, 0.001, clearcoat_gloss) (Burley 2012, appendix).")
#: Burley's subsurface lobe (:func:`subsurface`), +∞ where both directions lie on the horizon.
SUBSURFACE_FORMULA = Formula(
    "principled_subsurface", ("roughness", "mu_l", "mu_v", "l_dot_v"),
    "1.25 * (f_ss * (inv - 0.5) + 0.5) / PI",
    body=(("f90", "roughness * 0.5 * (1.0 + l_dot_v)"), *schlick_weight_body("mu_l", "wl"),
          *schlick_weight_body("mu_v", "wv"), ("f_ss", "(1.0 + (f90 - 1.0) * wl) * (1.0 + (f90 - 1.0) * wv)"),
          ("inv", "sel(mu_l + mu_v > 0.0, 1.0 / (mu_l + mu_v), INF())")),
    consts=PI_CONST,
    doc="Burley's subsurface lobe (no ρ): 1.25 (F_ss (1/(μ_l + μ_v) − 0.5) + 0.5)/π,\n"
        "F_ss = (1 + (F_ss90 − 1)(1 − μ_l)⁵)(1 + (F_ss90 − 1)(1 − μ_v)⁵), F_ss90 = r cos²θ_d (Burley 2012).")
#: Kulla-Conty's scale of one channel: F_ms/(π(1 − Ē)), F_ms = F̄² Ē/(1 − F̄(1 − Ē))
#: (docs/kulla_conty.md §2; app/integrate/compensation.py), 0 if the lobe loses nothing.
KC_SCALE_FORMULA = Formula(
    "principled_kc_scale", ("F_avg", "E_avg"),
    "sel(1.0 - E_avg > MIN_ENERGY_LOSS, F_avg * F_avg * E_avg / (1.0 - F_avg * (1.0 - E_avg)) / (PI * (1.0 - E_avg)), 0.0)",
    consts=(*PI_CONST, ("MIN_ENERGY_LOSS", MIN_ENERGY_LOSS, "below: the lobe loses nothing (compensation.py)")),
    doc="Kulla & Conty 2017: F_ms/(π(1 − Ē)), F_ms = F̄² Ē/(1 − F̄(1 − Ē)) (docs/kulla_conty.md §2).")
