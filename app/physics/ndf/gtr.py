"""Generalized Trowbridge-Reitz (GTR, Burley 2012): γ = 2 is GGX.

D(m) = k(α, γ) / (π (1 + (n·m)² (α² − 1))^γ). The normalisation k has removable
singularities at γ = 1 and α = 1, so it is formed as k = E(x) / E((1 − γ) x) with
x = ln α² and E(y) = (e^y − 1)/y, which is continuous through both.

Not shape-invariant: isotropic only, and its Smith Λ has no closed form; ``smith``
interpolates a table of the general Smith integral (smith_table.py). The tail mass beyond
r̃ = tanθ/α is in closed form, and radial_ccdf_inv solves it for μ².
(derivation: docs/ndfs.md §2)

References: Burley 2012, "Physically-Based Shading at Disney", SIGGRAPH course notes,
eq. 8 and appendix B (normalisation, sampling).
"""
from __future__ import annotations

import math

import numpy as np

from ..formula import Formula
from ..lambda_table import table_params, tabulated_mu_Lambda_scalar
from ..numeric import (SERIES_CUTOFF, expm1_ratio, expm1_ratio_scalar, log1p_ratio,
                       log1p_ratio_scalar, where_valid)
from ..params import Param
from ..scalar import scalar
from ..smith_table import mu_Lambda_tabulated
from .base import NDFS, SlopeSpaceNDF

# kernel_params layout: α², γ, k, ln α², k α^{2(1−γ)}, ln(k/π) + (2 − 2γ) ln α, then
# the tabulated μΛ (lambda_table.py) from TABLE_AT.
TABLE_AT = 6

GAMMA = Param("gamma", "γ (GTR tail: 2 = GGX)", 0.5, 10.0, 2.0,
              "GTR exponent: γ = 2 is GGX, γ = 1 is Berry's, smaller γ has longer tails.")


@NDFS.register
class GTR(SlopeSpaceNDF):
    name = "gtr"
    label = "GTR (generalized Trowbridge-Reitz)"
    menu_order = 3
    description = "Burley's generalisation of GGX with tail exponent γ; isotropic only."
    reference = "Burley 2012, eq. 8 and appendix B"
    shape_params = (GAMMA,)
    simplifies_to = (({"gamma": 2.0}, "ggx"),)
    shape_invariant = False
    anisotropic = False

    @property
    def k(self) -> float:
        x = np.log(self.alpha_x ** 2)
        return float(expm1_ratio(x) / expm1_ratio((1.0 - self.gamma) * x))

    def _D(self, mz, q2):
        # α² D with sin²θ = α² q² (mz² + q² ≥ min(1, 1/α²) > 0 for a unit m):  α² k / (π α^{2γ} (mz² + q²)^γ), in logs.
        a, g = self.alpha_x, self.gamma
        return np.exp(np.log(self.k / np.pi) + (2.0 - 2.0 * g) * np.log(a) - g * np.log(mz * mz + q2))

    def _mu_Lambda(self, mu, s):
        return mu_Lambda_tabulated(self, mu, s)

    def _B(self, r2):
        """μ₀² = cos²θ = 1/(1 + A r̃²), z = (1 − A) r̃² μ₀² and ln B, where
        B = 1 + μ₀²(A − 1) = A (1 + z) (A = α²). B is the base of D's denominator;
        forming it as 1 + μ₀²(A − 1) would lose 8 digits at α = 1e-4 (B ≈ 1e-8)."""
        A = self.alpha_x ** 2
        mu2 = 1.0 / (1.0 + A * r2)
        z = (1.0 - A) * r2 * mu2
        return mu2, z, np.log(A) + np.log1p(z)

    def radial_ccdf(self, r2):
        # k ∫_0^{μ₀²} (1 + y (A − 1))^{−γ} dy = k μ₀² E((1 − γ) ln B) · ln B/(B − 1).
        A, g = self.alpha_x ** 2, self.gamma
        r2 = np.asarray(r2, dtype=float)
        finite = np.isfinite(r2)
        mu2, _, log_B = self._B(np.where(finite, r2, 0.0))
        y = mu2 * (A - 1.0)                  # B − 1, no cancellation
        small = np.abs(y) < SERIES_CUTOFF    # ln B/(B − 1) → 1 − y/2 as A → 1
        ratio = np.where(small, 1.0 - 0.5 * y, where_valid(~small, [log_B, y], lambda lb, yy: lb / yy, 1.0))
        # ≤ 1 as a tail mass; at r̃ = 0 the product of three rounded factors came out
        # 1 + 1 ulp, and ln(1 − u) > 0 then made the albedo's log rule take √ of −1e-21
        # (a NaN, found by a RuntimeWarning in the furnace test): the bound is kept here.
        v = np.minimum(self.k * mu2 * expm1_ratio((1.0 - g) * log_B) * ratio, 1.0)
        return np.where(finite, v, 0.0)

    def radial_cdf(self, r2):
        # The mass within r̃, without 1 − (tail):
        # C = k B^{1−γ} E(−(1−γ) L) · log1p(z)/z · r̃² μ₀², L = log1p(z)
        # (→ k A^{1−γ} r̃² as r̃ → 0).
        g = self.gamma
        r2 = np.asarray(r2, dtype=float)
        finite = np.isfinite(r2)
        r2f = np.where(finite, r2, 0.0)
        mu2, z, log_B = self._B(r2f)
        c = (self.k * np.exp((1.0 - g) * log_B) * expm1_ratio(-(1.0 - g) * np.log1p(z))
             * log1p_ratio(z) * r2f * mu2)
        return np.where(finite, c, 1.0)

    def radial_cdf_inv(self, u):
        # Solve C(r̃) = u for r̃²: with w = u (γ − 1)(A − 1)/(k A^{1−γ}),
        # L₂ = log1p(w)/w · u (1 − A)/(k A^{1−γ}) = ln(B/A), Z = E(L₂) log1p(w)/w · u/(k A^{1−γ})
        # (= z/(1 − A)), r̃² = Z/(1 − A Z). No division by 1 − A or 1 − γ.
        # Mathematically w ≥ A^{γ−1} − 1 > −1; rounding near u = 1 may overshoot.
        A, g = self.alpha_x ** 2, self.gamma
        u = np.asarray(u, dtype=float)
        scale = u / (self.k * A ** (1.0 - g))
        w = np.maximum((g - 1.0) * (A - 1.0) * scale, -1.0 + np.finfo(float).eps)
        ratio = log1p_ratio(w)
        Z = expm1_ratio(ratio * (1.0 - A) * scale) * ratio * scale
        # 1 − A Z → 0 as u → 1 (r̃ → ∞); within rounding of u = 1 it reaches 0 or below:
        # that is r̃ = ∞ (use radial_ccdf_inv near u = 1, where this is ill-conditioned).
        return where_valid(1.0 - A * Z > 0, [Z], lambda zz: zz / (1.0 - A * zz), np.inf)

    def radial_ccdf_inv(self, v):
        # Solve k μ² E((1−γ)L) log1p(y)/y = v: with x_v = v(α² − 1)/k, z = (1 − γ) x_v,
        # μ² = (v/k) · E(log1p(z)/z · x_v) · log1p(z)/z  (no division by 1 − γ or α² − 1).
        v = np.asarray(v, dtype=float)
        x_v = v * (self.alpha_x ** 2 - 1.0) / self.k
        z = (1.0 - self.gamma) * x_v
        ratio = log1p_ratio(z)
        mu2 = v / self.k * expm1_ratio(ratio * x_v) * ratio
        # μ² ≤ 1; at v ≈ 1 (r̃ ≈ 0) rounding can put it a few ulps above 1, and r̃² = 0
        # is the value there.
        return np.maximum(1.0 / mu2 - 1.0, 0.0) / self.alpha_x ** 2

    def radial_params(self):
        A, g = self.alpha_x ** 2, self.gamma
        log_D0 = np.log(self.k / np.pi) + (2.0 - 2.0 * g) * np.log(self.alpha_x)
        return np.asarray([A, g, self.k, np.log(A), self.k * A ** (1.0 - g), log_D0], dtype=float)

    def kernel_params(self):
        return np.concatenate([self.radial_params(), table_params(self)])

    D_formula = Formula(
        "D_gtr", ("mz", "q2"), "exp(log_d0 - gamma * log(mz * mz + q2))",
        p=("a2", "gamma", "k", "log_a2", "k_a", "log_d0"),
        doc="GTR: α² D = exp(ln(k/π) + (2 − 2γ) ln α − γ ln(mz² + q²)), k(α, γ) of Burley 2012 (eq. 8,\n"
            "appendix B) formed once in float64 with expm1/log1p (kernel_params); mz² + q² ≥ min(1, 1/α²).")
    #: D_formula's ln(k/π) + (2 − 2γ) ln α from α and γ, for code that binds α at run time
    #: (the principled clearcoat's gloss as a uniform): k = E(x)/E((1 − γ)x), x = ln α²,
    #: E(y) = (e^y − 1)/y → 1 at y = 0 (Burley 2012, appendix B; radial_params forms the
    #: same in float64). α < 1 for the clearcoat (x ≤ ln 0.01), far from E's 0/0 at x = 0.
    log_d0_formula = Formula(
        "log_d0_gtr", ("alpha", "gamma"), "log(k / PI) + (2.0 - 2.0 * gamma) * log(alpha)",
        body=(("x", "2.0 * log(alpha)"), ("y", "(1.0 - gamma) * x"),
              ("e_x", "sel(x == 0.0, 1.0, expm1(x) / x)"), ("e_y", "sel(y == 0.0, 1.0, expm1(y) / y)"),
              ("k", "e_x / e_y")),
        consts=(("PI", math.pi, "π"),),
        doc="ln(k/π) + (2 − 2γ) ln α of GTR's D, k = E(ln α²)/E((1 − γ) ln α²), E(y) = (e^y − 1)/y (Burley 2012, app. B).")

    @staticmethod
    @scalar
    def mu_Lambda_scalar(mu, s2, p):
        return tabulated_mu_Lambda_scalar(mu, math.sqrt(s2), p, TABLE_AT)

    @staticmethod
    @scalar
    def radial_ccdf_scalar(r2, p):
        if not math.isfinite(r2):
            return 0.0
        A, g, k = p[0], p[1], p[2]
        mu2 = 1.0 / (1.0 + A * r2)
        log_B = p[3] + math.log1p((1.0 - A) * r2 * mu2)
        y = mu2 * (A - 1.0)
        ratio = 1.0 - 0.5 * y if abs(y) < SERIES_CUTOFF else log_B / y
        return min(k * mu2 * expm1_ratio_scalar((1.0 - g) * log_B) * ratio, 1.0)

    @staticmethod
    @scalar
    def radial_cdf_inv_scalar(u, p):
        A, g = p[0], p[1]
        scale = u / p[4]
        w = max((g - 1.0) * (A - 1.0) * scale, -1.0 + EPS)
        ratio = log1p_ratio_scalar(w)
        Z = expm1_ratio_scalar(ratio * (1.0 - A) * scale) * ratio * scale
        return Z / (1.0 - A * Z) if 1.0 - A * Z > 0.0 else math.inf

    @staticmethod
    @scalar
    def radial_ccdf_inv_scalar(v, p):
        A, g, k = p[0], p[1], p[2]
        x_v = v * (A - 1.0) / k
        ratio = log1p_ratio_scalar((1.0 - g) * x_v)
        mu2 = v / k * expm1_ratio_scalar(ratio * x_v) * ratio
        return max(1.0 / mu2 - 1.0, 0.0) / A


#: float64 machine epsilon (the floor of w in radial_cdf_inv).
EPS = float(np.finfo(float).eps)
