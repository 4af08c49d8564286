"""Hammon's diffuse for GGX + Smith microsurfaces (Hammon 2017, "PBR Diffuse Lighting
for GGX+Smith Microsurfaces", GDC), a fit to simulated multiple scattering between
Lambertian GGX microfacets:

f_d = ρ (f_single + ρ f_multi), f_single = ((1 − α) f_smooth + α f_rough)/π,
f_smooth = 1.05 (1 − (1 − μ_l)⁵)(1 − (1 − μ_v)⁵),
f_rough = F (0.9 − 0.4 F)(0.5 + n·h)/(n·h), F = ½ + ½ l·v,  f_multi = 0.1159 α,
α the GGX roughness of the specular model (for anisotropic α, √(α_x α_y)).

Reciprocal. Not exactly energy-conserving (a fit): see its albedo. n·h = (μ_l + μ_v)/‖l + v‖;
where both directions lie on the horizon n·h = 0 and f_rough is +inf (its limit) unless
l = −v (F = 0).
"""
from __future__ import annotations

import math

import numpy as np

from ..numeric import where_valid
from ..formula import Formula
from .base import DIFFUSES, F_D_ARGS, Diffuse, schlick_weight_body, schlick_weight, times_rho

#: Hammon's fitted constants (slides, "final formula").
SMOOTH_SCALE, ROUGH_A, ROUGH_B, MULTI = 1.05, 0.9, 0.4, 0.1159


@DIFFUSES.register
class Hammon(Diffuse):
    name = "hammon"
    label = "Hammon (GGX + Smith)"
    description = ("Diffuse under a GGX microsurface with Smith masking, fitted to simulation: "
                   "flattens and retro-reflects as α grows and adds ρ² 0.1159 α of multiple scattering.")
    reference = "Hammon 2017, PBR Diffuse Lighting for GGX+Smith Microsurfaces (GDC)"
    menu_order = 5
    uses_specular_roughness = True

    def f(self, rho, mu_l, mu_v, l_dot_v):
        a = self.alpha
        mu_l, mu_v = np.asarray(mu_l, dtype=float), np.asarray(mu_v, dtype=float)
        l_dot_v = np.asarray(l_dot_v, dtype=float)
        facing = 0.5 + 0.5 * l_dot_v
        # ‖l + v‖ = √(2 + 2 l·v); n·h = (μ_l + μ_v)/‖l + v‖ where l + v ≠ 0
        n_dot_h = where_valid(facing > 0, [mu_l + mu_v, facing], lambda m, fc: m / (2.0 * np.sqrt(fc)), 0.0)
        rough = where_valid(n_dot_h > 0, [facing, n_dot_h],
                            lambda fc, nh: fc * (ROUGH_A - ROUGH_B * fc) * (0.5 + nh) / nh,
                            np.where(facing > 0, np.inf, 0.0))
        smooth = SMOOTH_SCALE * (1.0 - schlick_weight(mu_l)) * (1.0 - schlick_weight(mu_v))
        single = ((1.0 - a) * smooth + times_rho(a, rough)) / np.pi
        rho = np.asarray(rho, dtype=float)
        return times_rho(rho, single) + rho * rho * MULTI * a

    def kernel_params(self):
        return (self.alpha,)

    f_formula = Formula(
        "fd_hammon", F_D_ARGS,
        "sel(rho == 0.0, 0.0, rho * single + rho * rho * MULTI * alpha)",
        body=(("facing", "0.5 + 0.5 * l_dot_v"),
              ("n_dot_h", "sel(facing > 0.0, (mu_l + mu_v) / (2.0 * sqrt(facing)), 0.0)"),
              ("rough", "sel(n_dot_h > 0.0, facing * (ROUGH_A - ROUGH_B * facing) * (0.5 + n_dot_h) / n_dot_h, "
                        "sel(facing > 0.0, INF(), 0.0))"),
              *schlick_weight_body("mu_l", "wl"), *schlick_weight_body("mu_v", "wv"),
              ("f_smooth", "SMOOTH_SCALE * (1.0 - wl) * (1.0 - wv)"),
              ("single", "((1.0 - alpha) * f_smooth + sel(alpha > 0.0, alpha * rough, 0.0)) / PI")),
        p=("alpha",),
        consts=(("PI", math.pi, "π"), ("SMOOTH_SCALE", SMOOTH_SCALE, "Hammon's fitted constant"),
                ("ROUGH_A", ROUGH_A, "Hammon's fitted constant"), ("ROUGH_B", ROUGH_B, "Hammon's fitted constant"),
                ("MULTI", MULTI, "Hammon's multiple-scattering constant")),
        doc="Hammon 2017 (GDC): f_d = ρ (((1 − α) f_smooth + α f_rough)/π + ρ 0.1159 α), f_smooth = 1.05 (1 − (1 − μ_l)⁵)\n"
            "(1 − (1 − μ_v)⁵), f_rough = F (0.9 − 0.4 F)(0.5 + n·h)/(n·h), F = ½ + ½ l·v.")
