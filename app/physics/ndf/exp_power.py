"""Exponential-power NDF (3-48, 3-49 as corrected in MATH.md): p = 1 is Beckmann.

P22(r̃) = p / (π Γ(1/p)) · exp(−(r̃²)^p) in stretched slopes (normalised:
∫ 2π r P22 dr = p/Γ(1/p) ∫ e^{−t^p} dt = 1), so D(m) carries the exponent
((1 − (n·m)²)/(α² (n·m)²))^p = (tan²θ_m/α²)^p. p is the kurtosis knob: p < 1 gives
longer tails than Beckmann, p > 1 shorter.

The mass beyond r̃ is the regularised upper incomplete gamma Q(1/p, r̃^{2p}).
Smith Λ (MATH.md's corrected (3-50)) has no closed form: ``smith`` interpolates a
table of the general Smith integral, one per p (the NDF is shape-invariant).

References
----------
Seed 000 (3-48)..(3-50); Heitz 2014 sec. 5 (shape invariance).
"""
from __future__ import annotations

import numpy as np
from scipy.special import gamma as gamma_fn
from scipy.special import gammainc, gammaincc, gammainccinv, gammaincinv

from . import register
from .base import SlopeSpaceNDF
from ..numeric import where_valid
from ..params import Param
from ..smith_table import mu_Lambda_tabulated

P = Param("p", "p (kurtosis: 1 = Beckmann)", 0.25, 4.0, 1.0,
          "Exponential-power shape: p = 1 is Beckmann; p < 1 longer tails, p > 1 shorter.")


@register
class ExpPower(SlopeSpaceNDF):
    name = "exp_power"
    label = "Exponential power"
    menu_order = 5
    description = "exp(−(tan²θ/α²)^p): p = 1 is Beckmann; p tunes the tail."
    reference = "seed 000 (3-48), (3-49) corrected in MATH.md"
    shape_params = (P,)

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
