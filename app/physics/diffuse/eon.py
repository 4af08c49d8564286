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
from ..scalar import scalar
from .base import DIFFUSES, Diffuse, times_rho

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
        r, a_f, _ = self._terms(0.0)
        return (r, a_f)

    @staticmethod
    @scalar
    def f_scalar(rho, mu_l, mu_v, l_dot_v, p):
        r, a_f = p[0], p[1]
        s = l_dot_v - mu_l * mu_v
        t = max(mu_l, mu_v)
        if rho == 0.0:
            return 0.0
        if s > 0.0 and t <= 0.0:
            return math.inf
        ratio = s / t if s > 0.0 else s
        avg = a_f * (1.0 + C2_SCALAR * r)
        rho_ms = rho * rho * avg / (1.0 - rho * (1.0 - avg))
        multi = a_f * r * (C1_SCALAR - G_scalar(mu_l) / math.pi) * (C1_SCALAR - G_scalar(mu_v) / math.pi)
        return (rho * a_f * (1.0 + r * ratio) + rho_ms * multi / (C1_SCALAR - C2_SCALAR)) / math.pi


C1_SCALAR, C2_SCALAR = C1, C2


@scalar
def G_scalar(mu):
    """:func:`G` for one value."""
    mu = min(max(mu, 0.0), 1.0)
    si = math.sqrt(1.0 - mu * mu)
    return si * (math.acos(mu) - si * mu) + (2.0 / 3.0) * (si * mu * (1.0 + si + si * si) / (1.0 + si) - si)
