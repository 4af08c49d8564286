"""Schlick's approximation, generalised: F = F₀ + (F₉₀ − F₀)(1 − cos θ)^p.

p = 5 and F₉₀ = 1 is Schlick 1994 (eq. 15); its error is shown against the exact
dielectric of the same F₀.
"""
from __future__ import annotations

import numpy as np

from ..params import Param
from ..formula import Formula
from .base import FRESNELS, Fresnel, clip_cos_scalar, _cos
from .dielectric import Dielectric, ior_from_f0

F0 = Param("f0", "F₀ (reflectance at 0°)", 0.0, 1.0, 0.04,
           "Reflectance at normal incidence (0.04 is a typical dielectric).")
F90 = Param("f90", "F₉₀ (reflectance at 90°)", 0.0, 1.0, 1.0,
            "Reflectance at grazing incidence.")
FRESNEL_P = Param("fresnel_p", "p (Schlick exponent)", 1.0, 10.0, 5.0,
                  "Exponent p of (1 − cos θ)^p in the generalised Schlick form; 5 is Schlick's.")


@FRESNELS.register
class Schlick(Fresnel):
    name = "schlick"
    label = "Schlick"
    description = ("F = F₀ + (F₉₀ − F₀)(1 − cos θ_d)^p: Schlick 1994 with p = 5, F₉₀ = 1; "
                   "its error is shown against the exact dielectric of the same F₀.")
    reference = "Schlick 1994, eq. 15"
    params = (F0, F90, FRESNEL_P)
    menu_order = 1
    approximates = "dielectric"
    simplifies_to = (({"f0": 1.0, "f90": 1.0}, "none"),)

    def F(self, cos_theta_d):
        return self.f0 + (self.f90 - self.f0) * (1.0 - _cos(cos_theta_d)) ** self.fresnel_p

    def F_avg(self):
        """2 ∫₀¹ (F₀ + (F₉₀ − F₀)(1 − μ)^p) μ dμ = F₀ + 2(F₉₀ − F₀)/((p + 1)(p + 2)), since
        2 ∫₀¹ (1 − μ)^p μ dμ = 2 B(2, p + 1); for p = 5, F₉₀ = 1 it is (20 F₀ + 1)/21."""
        p = self.fresnel_p
        return self.f0 + 2.0 * (self.f90 - self.f0) / ((p + 1.0) * (p + 2.0))

    #: F_avg as a formula of the parameters (what generated code forms when F₀ is a
    #: uniform: the principled BRDF's per-channel Kulla-Conty scale).
    F_avg_formula = Formula(
        "F_avg_schlick", (), "f0 + 2.0 * (f90 - f0) / ((fresnel_p + 1.0) * (fresnel_p + 2.0))",
        p=("f0", "f90", "fresnel_p"),
        doc="F_avg = 2 ∫ F μ dμ = F₀ + 2(F₉₀ − F₀)/((p + 1)(p + 2)) of Schlick's F (2 B(2, p + 1)).")

    def schlick_basis(self):
        return ((self.f0, None), (self.f90 - self.f0, self.fresnel_p))

    def exact_counterpart(self):
        """The exact dielectric with the same F₀: η = (1 + √F₀)/(1 − √F₀) (F₀ = 1 is the
        limit η → ∞, a perfect mirror)."""
        return Dielectric(ior=float(ior_from_f0(self.f0)))

    # Schlick's p = 5 by multiplication (a pow costs as much as the rest of f), and the clamp
    # as two selects: the compiled loops vectorise only so (app/kernels/compose.py,
    # UNSWITCH_THRESHOLD: 39 against 141 M/s per core)
    F_formula = Formula(
        "F_schlick", ("c",), "f0 + (f90 - f0) * sel(fresnel_p == 5.0, x2 * x2 * x, pow(x, fresnel_p))",
        body=(("x", "1.0 - sel(c > 1.0, 1.0, sel(c < 0.0, 0.0, c))"), ("x2", "x * x")), p=("f0", "f90", "fresnel_p"),
        doc="Schlick 1994, eq. 15, generalised: F = F₀ + (F₉₀ − F₀)(1 − cos θ_d)^p.")
