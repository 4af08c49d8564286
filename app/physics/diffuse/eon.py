"""EON, the energy-preserving Oren–Nayar of OpenPBR (Portsmouth, Kutz & Hill 2025,
"EON: A practical energy-preserving rough diffuse BRDF", JCGT 14(1); OpenPBR 1.1).

Single scattering is Fujii's Oren–Nayar (FON): f_ss = ρ/π A_F (1 + r s/t), s = l·v − μ_l μ_v,
t = max(μ_l, μ_v) where s > 0 else 1, A_F = 1/(1 + c₁ r), c₁ = 1/2 − 2/(3π), r ∈ [0, 1].
Its albedo is exact: E_F(μ) = A_F (1 + r G(θ)/π), G = sin θ (θ − sin θ cos θ)
+ ⅔ tan θ (1 − sin³θ) − ⅔ sin θ, and E_F,avg = A_F (1 + c₂ r), c₂ = 2/3 − 28/(15π).
The multiple-scattering lobe f_ms = ρ_ms/π (1 − E_F(μ_l))(1 − E_F(μ_v))/(1 − E_F,avg),
ρ_ms = ρ² E_F,avg/(1 − ρ(1 − E_F,avg)), restores what single scattering loses: with ρ = 1
the albedo is exactly 1 for every μ (white furnace), E = ρ E_F + ρ_ms (1 − E_F). The ratio
is written with r factored out, (1 − E_F) = A_F r (c₁ − G/π), so r = 0 needs no epsilon.
"""
from __future__ import annotations

import math

import numpy as np

from ..numeric import where_valid
from ..params import Param
from ..formula import Formula
from .base import DIFFUSES, F_D_ARGS, Diffuse, times_rho

ROUGHNESS_ON = Param("diffuse_roughness", "r (diffuse roughness)", 0.0, 1.0, 0.5,
                     "Roughness of the EON diffuse in [0, 1] (OpenPBR's base_diffuse_roughness).")
C1 = 0.5 - 2.0 / (3.0 * math.pi)
C2 = 2.0 / 3.0 - 28.0 / (15.0 * math.pi)


def G(mu) -> np.ndarray:
    """G(θ) of E_F; (sin θ/μ)(1 − sin³θ) = sin θ μ (1 + sin θ + sin²θ)/(1 + sin θ), which
    is finite at μ = 0 (1 − sin θ = μ²/(1 + sin θ))."""
    mu = np.clip(np.asarray(mu, dtype=float), 0.0, 1.0)
    si = np.sqrt(1.0 - mu * mu)
    tan_term = si * mu * (1.0 + si + si * si) / (1.0 + si)
    return si * (np.arccos(mu) - si * mu) + (2.0 / 3.0) * (tan_term - si)


def _G_body(mu: str, name: str) -> tuple[tuple[str, str], ...]:
    """:func:`G` of ``mu`` as formula assignments."""
    return ((f"{name}_m", f"clamp({mu}, 0.0, 1.0)"), (f"{name}_s", f"sqrt(1.0 - {name}_m * {name}_m)"),
            (name, f"{name}_s * (acos({name}_m) - {name}_s * {name}_m) + (2.0 / 3.0) * ({name}_s * {name}_m * "
                   f"(1.0 + {name}_s + {name}_s * {name}_s) / (1.0 + {name}_s) - {name}_s)"))


@DIFFUSES.register
class EON(Diffuse):
    name = "eon"
    label = "EON (energy-preserving Oren–Nayar)"
    description = ("OpenPBR's diffuse: Fujii's Oren–Nayar plus a multiple-scattering lobe, so that a "
                   "white surface reflects all the light (white furnace exact), ρ_ms saturating the colour.")
    reference = "Portsmouth, Kutz & Hill 2025, EON (JCGT 14(1)); OpenPBR 1.1"
    params = (ROUGHNESS_ON,)
    menu_order = 4
    conserves_energy = True

    def _terms(self, rho):
        r = self.diffuse_roughness
        a_f = 1.0 / (1.0 + C1 * r)
        avg = a_f * (1.0 + C2 * r)
        rho = np.asarray(rho, dtype=float)
        rho_ms = rho * rho * avg / (1.0 - rho * (1.0 - avg))
        return r, a_f, rho_ms

    def f(self, rho, mu_l, mu_v, l_dot_v):
        r, a_f, rho_ms = self._terms(rho)
        mu_l, mu_v = np.asarray(mu_l, dtype=float), np.asarray(mu_v, dtype=float)
        s = np.asarray(l_dot_v, dtype=float) - mu_l * mu_v
        t = np.maximum(mu_l, mu_v)
        # s/t where s > 0 (+inf where both graze, its limit), s itself where s ≤ 0
        s_over_t = np.where(s > 0, where_valid(t > 0, [s, t], lambda a, b: a / b, np.inf), s)
        single = times_rho(rho, a_f * (1.0 + r * s_over_t) / np.pi)
        multi = (a_f * r * (C1 - G(mu_l) / math.pi) * (C1 - G(mu_v) / math.pi) / (C1 - C2))
        return single + rho_ms / np.pi * multi

    def albedo(self, rho, mu):
        r, a_f, rho_ms = self._terms(rho)
        e_f = a_f * (1.0 + r * G(np.atleast_1d(mu)) / math.pi)
        return rho * e_f + rho_ms * (1.0 - e_f), 0.0

    def kernel_params(self):
        """(r,): A_F is formed from r inside the formula, so generated code that binds r
        per pixel (a uniform, a texture) keeps A_F consistent with it."""
        return (self.diffuse_roughness,)

    f_formula = Formula(
        "fd_eon", F_D_ARGS,
        "sel(rho == 0.0, 0.0, sel(and_(s > 0.0, t <= 0.0), INF(), "
        "(rho * a_f * (1.0 + r * ratio) + rho_ms * multi / (C1 - C2)) / PI))",
        body=(("a_f", "1.0 / (1.0 + C1 * r)"), ("s", "l_dot_v - mu_l * mu_v"), ("t", "max(mu_l, mu_v)"),
              ("ratio", "sel(and_(s > 0.0, t > 0.0), s / t, s)"),
              ("avg", "a_f * (1.0 + C2 * r)"),
              ("rho_ms", "rho * rho * avg / (1.0 - rho * (1.0 - avg))"),
              *_G_body("mu_l", "G_l"), *_G_body("mu_v", "G_v"),
              ("multi", "a_f * r * (C1 - G_l / PI) * (C1 - G_v / PI)")),
        p=("r",),
        consts=(("PI", math.pi, "π"), ("C1", C1, "1/2 − 2/(3π)"), ("C2", C2, "2/3 − 28/(15π)")),
        doc="EON (Portsmouth, Kutz & Hill 2025): Fujii's Oren–Nayar ρ/π A_F (1 + r s/t) plus the multiple-\n"
            "scattering lobe ρ_ms/π (1 − E_F(μ_l))(1 − E_F(μ_v))/(1 − E_F,avg); +∞ where both graze with s > 0.")
