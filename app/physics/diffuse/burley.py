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

import math

from ..formula import Formula
from .base import DIFFUSES, F_D_ARGS, Diffuse, schlick_weight, schlick_weight_body


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

    f_formula = Formula(
        "fd_burley", F_D_ARGS, "rho / PI * (1.0 + (f_d90 - 1.0) * wl) * (1.0 + (f_d90 - 1.0) * wv)",
        body=(("f_d90", "0.5 + roughness * (1.0 + l_dot_v)"),
              *schlick_weight_body("mu_l", "wl"), *schlick_weight_body("mu_v", "wv")),
        p=("roughness",), consts=(("PI", math.pi, "π"),),
        doc="Burley 2012 (sec. 5.3): f_d = ρ/π (1 + (F_D90 − 1)(1 − μ_l)⁵)(1 + (F_D90 − 1)(1 − μ_v)⁵),\n"
            "F_D90 = 0.5 + 2 r cos²θ_d = 0.5 + r (1 + l·v), r the perceptual roughness √α.")
