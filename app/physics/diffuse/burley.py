"""Burley's diffuse (Burley 2012, "Physically-Based Shading at Disney", sec. 5.3):

f_d = ρ/π (1 + (F_D90 − 1)(1 − μ_l)⁵)(1 + (F_D90 − 1)(1 − μ_v)⁵),
F_D90 = 0.5 + 2 r cos²θ_d, θ_d the angle between l and h, r the perceptual roughness of
the specular model (r = √α; for anisotropic α, r = (α_x α_y)^¼, see BRDF).

cos²θ_d = (1 + l·v)/2, so F_D90 = 0.5 + r(1 + l·v), defined everywhere. Reciprocal. Not
energy-conserving: at a grazing view a white surface reflects E_d(1, 0) ≈ 1.56 at r = 1
(retro-reflection) and ≈ 0.49 at r = 0; at normal view ≈ 1.04 and ≈ 0.98.
"""
from __future__ import annotations

import numpy as np

from ..scalar import scalar
from .base import DIFFUSES, Diffuse, schlick_weight


@DIFFUSES.register
class Burley(Diffuse):
    name = "burley"
    label = "Burley (Disney)"
    description = ("f_d = ρ/π (1 + (F_D90 − 1)(1 − μ_l)⁵)(1 + (F_D90 − 1)(1 − μ_v)⁵), F_D90 = 0.5 + "
                   "2 r cos²θ_d with r the specular roughness: retro-reflective at grazing, not "
                   "energy-conserving.")
    reference = "Burley 2012, Physically-Based Shading at Disney, sec. 5.3"
    menu_order = 2
    uses_specular_roughness = True

    @property
    def roughness(self) -> float:
        return float(np.sqrt(self.alpha))

    def f(self, rho, mu_l, mu_v, l_dot_v):
        f_d90 = 0.5 + self.roughness * (1.0 + np.asarray(l_dot_v, dtype=float))
        return (np.asarray(rho, dtype=float) / np.pi * (1.0 + (f_d90 - 1.0) * schlick_weight(mu_l))
                * (1.0 + (f_d90 - 1.0) * schlick_weight(mu_v)))

    def kernel_params(self):
        return (self.roughness,)

    @staticmethod
    @scalar
    def f_scalar(rho, mu_l, mu_v, l_dot_v, p):
        f_d90 = 0.5 + p[0] * (1.0 + l_dot_v)
        wl = (1.0 - min(max(mu_l, 0.0), 1.0)) ** 5
        wv = (1.0 - min(max(mu_v, 0.0), 1.0)) ** 5
        return rho / 3.141592653589793 * (1.0 + (f_d90 - 1.0) * wl) * (1.0 + (f_d90 - 1.0) * wv)
