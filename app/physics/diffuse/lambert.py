"""Lambert: f_d = ρ/π (Lambert 1760, "Photometria"). E_d = ρ exactly for every μ."""
from __future__ import annotations

import numpy as np

import math

from ..formula import Formula
from .base import DIFFUSES, F_D_ARGS, Diffuse


@DIFFUSES.register
class Lambert(Diffuse):
    name = "lambert"
    label = "Lambert"
    description = "f_d = ρ/π: the ideal diffuse reflector; E_d = ρ for every view (white furnace exact)."
    reference = "Lambert 1760, Photometria"
    menu_order = 1
    conserves_energy = True

    def f(self, rho, mu_l, mu_v, l_dot_v):
        return np.broadcast_to(np.asarray(rho, dtype=float) / np.pi,
                               np.broadcast_shapes(np.shape(mu_l), np.shape(mu_v), np.shape(l_dot_v)))

    def albedo(self, rho, mu):
        return np.full(np.shape(np.atleast_1d(mu)), float(rho)), 0.0

    def albedo_avg(self, rho):
        return float(rho), 0.0

    f_formula = Formula("fd_lambert", F_D_ARGS, "rho / PI", consts=(("PI", math.pi, "π"),),
                        doc="Lambert: f_d = ρ/π.")
