"""F = 1: no interface term (the white-furnace setting)."""
from __future__ import annotations

import numpy as np

from ..formula import Formula
from .base import FRESNELS, Fresnel


@FRESNELS.register
class NoFresnel(Fresnel):
    name = "none"
    label = "None (F = 1)"
    description = "F = 1: shows D and G alone; with it the white-furnace tests apply."
    menu_order = 0

    def F(self, cos_theta_d):
        return np.ones_like(np.asarray(cos_theta_d, dtype=float))

    def F_avg(self):
        return 1.0

    def schlick_basis(self):
        return ((1.0, None),)

    F_formula = Formula("F_none", ("c",), "1.0", doc="F = 1.")
