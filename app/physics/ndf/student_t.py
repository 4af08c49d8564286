"""Student-t NDF (Ribardière et al. 2017): between GGX (γ = 2) and Beckmann (γ → ∞).

In stretched slopes P22(r̃) = (1/π) (1 + r̃²/(γ − 1))^{−γ}, with tail mass
1 − C(r̃) = (1 + r̃²/(γ − 1))^{1−γ}: written so that (γ − 1)^γ, which overflows for large
γ, never appears. Smith Λ in closed form (Heitz 2014, eq. 72, from the marginal slope
density g, a scaled Student-t): μΛ = s (T₁ − a T₂) with T₁ = ∫_a^∞ x g =
c (γ−1)/(2γ−3) (1 + a²/(γ−1))^{3/2−γ} (c: g's normalisation) and T₂ = ∫_a^∞ g =
½ I_{(γ−1)/(γ−1+a²)}(γ − 1, ½) (regularised incomplete beta), computed as the tail
itself, not 1 − CDF (precision at large a); finite only for γ > 1.5.
(derivation: docs/ndfs.md §3)

References: Ribardière, Bringier, Meneveaux, Simonot 2017, "STD: Student's t-Distribution
of Slopes for Microfacet Based BRDFs", Computer Graphics Forum 36(2).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.special import betainc, gammaln

from ..formula import Formula
from ..numeric import where_valid
from ..params import Param
from ..scalar import scalar
from .base import NDFS, SlopeSpaceNDF

GAMMA = Param("gamma", "γ (tail: 2 = GGX, ∞ = Beckmann)", 1.5, 1000.0, 2.0,
              "Student-t shape: γ = 2 is GGX, γ → ∞ tends to Beckmann; Λ exists for γ > 1.5.",
              lo_open=True, scale="log")

# exp() of more than this overflows float64; D's horizon limit is +inf there (γ < 2).
LOG_MAX = 709.0


@NDFS.register
class StudentT(SlopeSpaceNDF):
    name = "student_t"
    label = "Student-t"
    menu_order = 4
    description = "Slope distribution with a tunable tail: γ = 2 is GGX, γ → ∞ is Beckmann."
    reference = "Ribardière et al. 2017"
    shape_params = (GAMMA,)
    simplifies_to = (({"gamma": 2.0}, "ggx"),)

    @property
    def tail_beta(self) -> float:
        # v = (1 + r̃²/(γ−1))^{1−γ} ~ r̃^{2−2γ}: r̃ ~ v^{−1/(2γ−2)}
        return 1.0 / (2.0 * self.gamma - 2.0)

    def _D(self, mz, q2):
        # α_x α_y D = P22(q²/mz²)/mz⁴ = mz^{2γ−4} / (π (mz² + q²/(γ−1))^γ), in logs.
        # At mz = 0 the limit is 0 for γ > 2, 1/(π q⁴) for γ = 2 and +inf for γ < 2.
        g = self.gamma

        def inside(z, q):
            log_d = (2.0 * g - 4.0) * np.log(z) - g * np.log(z * z + q / (g - 1.0))
            return where_valid(log_d < LOG_MAX, [log_d], lambda x: np.exp(x) / np.pi, np.inf)

        if g > 2.0:
            horizon = 0.0
        elif g == 2.0:
            horizon = where_valid(q2 > 0, [q2], lambda q: 1.0 / (np.pi * q * q), np.inf)
        else:
            horizon = np.inf
        return where_valid(mz > 0, [mz, q2], inside, horizon)

    @property
    def _log_c(self) -> float:
        g = self.gamma
        return gammaln(g - 0.5) - gammaln(g - 1.0) - 0.5 * np.log(np.pi * (g - 1.0))

    def _mu_Lambda(self, mu, s):
        g = self.gamma
        log_c = self._log_c

        def formula(mu, s):
            a = mu / s
            t1 = np.exp(log_c + (1.5 - g) * np.log1p(a * a / (g - 1.0))) * (g - 1.0) / (2.0 * g - 3.0)
            t2 = 0.5 * betainc(g - 1.0, 0.5, (g - 1.0) / (g - 1.0 + a * a))
            return s * (t1 - a * t2)
        return where_valid(s > 0, [mu, s], formula, 0.0)

    def radial_ccdf(self, r2):
        g = self.gamma
        return np.exp((1.0 - g) * np.log1p(r2 / (g - 1.0)))

    def radial_ccdf_inv(self, v):
        g = self.gamma
        return (g - 1.0) * np.expm1(-np.log(v) / (g - 1.0))

    def radial_cdf(self, r2):
        g = self.gamma
        return -np.expm1((1.0 - g) * np.log1p(r2 / (g - 1.0)))

    def radial_cdf_inv(self, u):
        g = self.gamma
        return (g - 1.0) * np.expm1(-np.log1p(-u) / (g - 1.0))

    # p = (γ, ln c of the marginal, exponent 2γ − 4 of D)
    def kernel_params(self):
        return (self.gamma, float(self._log_c), 2.0 * self.gamma - 4.0)

    D_formula = Formula(
        "D_student_t", ("mz", "q2"),
        "sel(mz > 0.0, sel(log_d < LOG_MAX, exp(log_d) / PI, INF()), "
        "sel(gamma > 2.0, 0.0, sel(and_(gamma == 2.0, q2 > 0.0), 1.0 / (PI * q2 * q2), INF())))",
        body=(("log_d", "e * log(max(mz, MZ_FLOOR)) - gamma * log(mz * mz + q2 / (gamma - 1.0))"),),
        p=("gamma", "log_c", "e"),
        consts=(("PI", math.pi, "π"), ("LOG_MAX", LOG_MAX, "exp overflows float64 beyond: +∞"),
                ("MZ_FLOOR", 1e-30, "keeps the side not selected at mz = 0 finite (float32 has it)")),
        doc="Student-t: α_x α_y D = mz^(2γ−4) / (π (mz² + q²/(γ − 1))^γ), in logs (Ribardière et al. 2017);\n"
            "at mz = 0 its limit: 0 for γ > 2, 1/(π q⁴) for γ = 2, +∞ for γ < 2.")

    @staticmethod
    @scalar
    def mu_Lambda_scalar(mu, s2, p):
        if not s2 > 0.0:
            return 0.0
        s = math.sqrt(s2)
        g = p[0]
        a = mu / s
        t1 = math.exp(p[1] + (1.5 - g) * math.log1p(a * a / (g - 1.0))) * (g - 1.0) / (2.0 * g - 3.0)
        t2 = 0.5 * betainc(g - 1.0, 0.5, (g - 1.0) / (g - 1.0 + a * a))
        return s * (t1 - a * t2)

    @staticmethod
    @scalar
    def radial_ccdf_scalar(r2, p):
        g = p[0]
        return math.exp((1.0 - g) * math.log1p(r2 / (g - 1.0)))

    @staticmethod
    @scalar
    def radial_cdf_inv_scalar(u, p):
        g = p[0]
        return (g - 1.0) * math.expm1(-math.log1p(-u) / (g - 1.0))

    @staticmethod
    @scalar
    def radial_ccdf_inv_scalar(v, p):
        g = p[0]
        return (g - 1.0) * math.expm1(-math.log(v) / (g - 1.0))
