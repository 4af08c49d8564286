"""Exponential-power NDF: p = 1 is Beckmann; p < 1 gives longer tails, p > 1 shorter.

P22(r̃) = p / (π Γ(1/p)) · exp(−(r̃²)^p) in stretched slopes (normalised), so D(m) carries
the exponent (tan²θ_m/α²)^p. The mass beyond r̃ is the regularised upper incomplete gamma
Q(1/p, r̃^{2p}). Its Smith Λ (Heitz 2014, eq. 72, from the marginal slope density) has no
closed form: ``smith`` interpolates a table of the general Smith integral, one per p (the
NDF is shape-invariant).
(derivation: docs/ndfs.md §4)

References: Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based
BRDFs", JCGT 3(2), sec. 5 (shape invariance) and eq. 72 (Λ from the slopes).
"""
from __future__ import annotations

import math

import numpy as np
from scipy.special import gamma as gamma_fn
from scipy.special import gammainc, gammaincc, gammainccinv, gammaincinv

from ..lambda_table import table_params, tabulated_mu_Lambda_scalar
from ..numeric import where_valid
from ..params import Param
from ..scalar import scalar
from ..smith_table import mu_Lambda_tabulated
from .base import NDFS, SlopeSpaceNDF

# kernel_params layout: p, 1/p, p/(π Γ(1/p)), then the tabulated μΛ from TABLE_AT.
TABLE_AT = 3

P = Param("p", "p (kurtosis: 1 = Beckmann)", 0.25, 4.0, 1.0,
          "Exponential-power shape: p = 1 is Beckmann; p < 1 longer tails, p > 1 shorter.")


@NDFS.register
class ExpPower(SlopeSpaceNDF):
    name = "exp_power"
    label = "Exponential power"
    menu_order = 5
    description = "exp(−(tan²θ/α²)^p): p = 1 is Beckmann; p tunes the tail."
    reference = "Heitz 2014, sec. 5"
    shape_params = (P,)
    simplifies_to = (({"p": 1.0}, "beckmann"),)

    @property
    def tail_beta(self) -> float:
        return 0.0  # v ~ e^{−r̃^{2p}}: r̃ grows like (−ln v)^{1/(2p)}

    def _D(self, mz, q2):
        # α_x α_y D = p/(π Γ(1/p)) exp(−(q²/mz²)^p − 4 ln mz), 0 in the limit mz → 0.
        p = self.p
        norm = p / (np.pi * gamma_fn(1.0 / p))

        def inside(z, q):
            tail = where_valid(q > 0, [q, z], lambda qq, zz: np.exp(p * (np.log(qq) - 2.0 * np.log(zz))), 0.0)
            return norm * np.exp(-tail - 4.0 * np.log(z))
        return where_valid(mz > 0, [mz, q2], inside, 0.0)

    def _mu_Lambda(self, mu, s):
        return mu_Lambda_tabulated(self, mu, s)

    def radial_ccdf(self, r2):
        return gammaincc(1.0 / self.p, np.power(r2, self.p))

    def radial_ccdf_inv(self, v):
        return np.power(gammainccinv(1.0 / self.p, v), 1.0 / self.p)

    def radial_cdf(self, r2):
        return gammainc(1.0 / self.p, np.power(r2, self.p))

    def radial_cdf_inv(self, u):
        return np.power(gammaincinv(1.0 / self.p, u), 1.0 / self.p)

    def kernel_params(self):
        p = self.p
        head = [p, 1.0 / p, p / (np.pi * gamma_fn(1.0 / p))]
        return np.concatenate([np.asarray(head, dtype=float), table_params(self)])

    @staticmethod
    @scalar
    def D_scalar(mz, q2, p):
        if not mz > 0.0:
            return 0.0
        tail = math.exp(p[0] * (math.log(q2) - 2.0 * math.log(mz))) if q2 > 0.0 else 0.0
        return p[2] * math.exp(-tail - 4.0 * math.log(mz))

    @staticmethod
    @scalar
    def mu_Lambda_scalar(mu, s, p):
        return tabulated_mu_Lambda_scalar(mu, s, p, TABLE_AT)

    @staticmethod
    @scalar
    def radial_ccdf_scalar(r2, p):
        return gammaincc(p[1], r2 ** p[0])

    @staticmethod
    @scalar
    def radial_cdf_inv_scalar(u, p):
        return gammaincinv(p[1], u) ** p[1]

    @staticmethod
    @scalar
    def radial_ccdf_inv_scalar(v, p):
        return gammainccinv(p[1], v) ** p[1]
