"""Fresnel reflectance F(cos θ_d), θ_d the angle between l (or v) and h (MATH.md errata).

References
----------
Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", eq. 15;
seed 000 (2-3).
"""
from __future__ import annotations

from typing import ClassVar

import numpy as np

from .params import Param

F0 = Param("f0", "F₀ (reflectance at 0°)", 0.0, 1.0, 0.04,
           "Reflectance at normal incidence (0.04 is a typical dielectric).")
F90 = Param("f90", "F₉₀ (reflectance at 90°)", 0.0, 1.0, 1.0,
            "Reflectance at grazing incidence.")


class Fresnel:
    name: ClassVar[str]
    label: ClassVar[str]
    description: ClassVar[str]
    params: ClassVar[tuple[Param, ...]] = ()

    def __init__(self, **values: float):
        for p in self.params:
            setattr(self, p.name, float(values.get(p.name, p.default)))

    def F(self, cos_theta_d) -> np.ndarray:
        raise NotImplementedError


class NoFresnel(Fresnel):
    name = "none"
    label = "None (F = 1)"
    description = "F = 1: shows D and G alone; with it the white-furnace tests apply."

    def F(self, cos_theta_d):
        return np.ones_like(np.asarray(cos_theta_d, dtype=float))


class Schlick(Fresnel):
    name = "schlick"
    label = "Schlick"
    description = "F = F₀ + (F₉₀ − F₀)(1 − cos θ_d)⁵ (Schlick 1994)."
    params = (F0, F90)

    def F(self, cos_theta_d):
        c = np.clip(np.asarray(cos_theta_d, dtype=float), 0.0, 1.0)
        return self.f0 + (self.f90 - self.f0) * (1.0 - c) ** 5


FRESNELS: dict[str, type[Fresnel]] = {cls.name: cls for cls in (NoFresnel, Schlick)}
