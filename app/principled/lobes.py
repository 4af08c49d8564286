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
from ..physics.diffuse.base import schlick_weight, times_rho
from ..physics.fresnel import FRESNELS
from ..physics.masking import MASKINGS
from ..physics.ndf import NDFS
from ..physics.numeric import where_valid
from ..physics.vectors import dot
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


def diffuse_model(material):
    """The registry's diffuse model the option names, at the material's roughness."""
    r = material.roughness
    choice = material.options["principled_diffuse"]
    if choice == "burley":
        return DIFFUSES["burley"](alpha=r * r)
    if choice == "eon":
        return DIFFUSES["eon"](diffuse_roughness=r)
    return DIFFUSES["lambert"]()


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
