"""Exponential-power NDF: p = 1 is Beckmann; p < 1 gives longer tails, p > 1 shorter.

P22(r̃) = p / (π Γ(1/p)) · exp(−(r̃²)^p) in stretched slopes (normalised), so D(m) carries
the exponent (tan²θ_m/α²)^p. The mass beyond r̃ is the regularised upper incomplete gamma
Q(1/p, r̃^{2p}). Its Smith Λ (Heitz 2014, eq. 72, from the marginal slope density) has no
closed form: ``smith`` interpolates a table of the general Smith integral, one per p (the
NDF is shape-invariant). The radial inverses solve P(1/p, x) = u or Q(1/p, x) = v by a
guess from a per-p table and one Halley step (``_inverse``): ~4× cheaper than scipy's
gammaincinv, as accurate (tests/physics/test_gamma_inverse.py). (derivation: docs/ndfs.md §4)

References: Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based
BRDFs", JCGT 3(2), sec. 5 and eq. 72; Gil, Segura & Temme 2012, "Efficient and accurate
algorithms for the computation and inversion of the incomplete gamma function ratios",
SIAM J. Sci. Comput. 34(6), sec. 4 (Halley's iteration, as in Boost's gamma_p_inv).
"""
from __future__ import annotations

import math
from functools import lru_cache

import numpy as np
from scipy.interpolate import CubicHermiteSpline
from scipy.special import gamma as gamma_fn
from scipy.special import gammainc, gammaincc, gammainccinv, gammaincinv, gammaln

from ..formula import Formula
from ..lambda_table import table_params, tabulated_mu_Lambda_scalar
from ..numeric import where_valid
from ..params import Param
from ..scalar import scalar
from ..smith_table import mu_Lambda_tabulated
from .base import NDFS, SlopeSpaceNDF

#: Nodes of each guess table of the inverse (P and Q branch): a cubic Hermite in ln x
#: with exact slopes; its relative error (≤ 1e-7, measured at p = 0.25 to 4) is cubed
#: by the Halley step, far below rounding.
INV_NODES = 1024
#: Below this u the P-branch guess is the series' first term x = (u Γ(a+1))^{1/a}, whose
#: relative error ≈ x/(a+1) ≤ 1e-7 for every a = 1/p ∈ [0.25, 4] (x ≤ 7e-8 there).
INV_U_MIN = 1e-30
#: Q-branch table in z = ln(−ln v) for v from 1/2 down to the smallest subnormal
#: (−ln v ≤ 744.5): z ∈ [ln ln 2, ln 745].
INV_ZQ_MAX = math.log(745.0)
#: Floats of the inverse's block in kernel_params before its two coefficient tables:
#: lnΓ(a), lnΓ(a + 1), then (z₀, dz) of the P table and of the Q table.
INV_HEADER = 6
#: kernel_params layout: p, 1/p, p/(π Γ(1/p)), the inverse's block from INV_AT, then the
#: tabulated μΛ from TABLE_AT.
INV_AT = 3
TABLE_AT = INV_AT + INV_HEADER + 8 * (INV_NODES - 1)

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
        v = np.asarray(v, dtype=float)
        return np.power(_inverse(_inverse_params(self.p), 1.0 - v, v, 1.0 / self.p), 1.0 / self.p)

    def radial_cdf(self, r2):
        return gammainc(1.0 / self.p, np.power(r2, self.p))

    def radial_cdf_inv(self, u):
        u = np.asarray(u, dtype=float)
        return np.power(_inverse(_inverse_params(self.p), u, 1.0 - u, 1.0 / self.p), 1.0 / self.p)

    def radial_params(self):
        p = self.p
        head = [p, 1.0 / p, p / (np.pi * gamma_fn(1.0 / p))]
        return np.concatenate([np.asarray(head, dtype=float), _inverse_params(p)])

    def kernel_params(self):
        return np.concatenate([self.radial_params(), table_params(self)])

    D_formula = Formula(
        "D_exp_power", ("mz", "q2"), "sel(mz > 0.0, norm * exp(-tail - 4.0 * lmz), 0.0)",
        body=(("lmz", "log(max(mz, MZ_FLOOR))"),
              ("tail", "sel(q2 > 0.0, exp(p_exp * (log(max(q2, MZ_FLOOR)) - 2.0 * lmz)), 0.0)")),
        p=("p_exp", "inv_p", "norm"),
        consts=(("MZ_FLOOR", 1e-30, "keeps the side not selected finite (mz = 0 or q² = 0); float32 has it"),),
        doc="Exponential power: α_x α_y D = p/(π Γ(1/p)) exp(−(q²/mz²)^p) / mz⁴ (p = 1 is Beckmann), in logs.")

    @staticmethod
    @scalar
    def mu_Lambda_scalar(mu, s2, p):
        return tabulated_mu_Lambda_scalar(mu, math.sqrt(s2), p, TABLE_AT)

    @staticmethod
    @scalar
    def radial_ccdf_scalar(r2, p):
        return gammaincc(p[1], r2 ** p[0])

    @staticmethod
    @scalar
    def radial_cdf_inv_scalar(u, p):
        return inverse_scalar(u, 1.0 - u, p, INV_AT, p[1]) ** p[1]

    @staticmethod
    @scalar
    def radial_ccdf_inv_scalar(v, p):
        return inverse_scalar(1.0 - v, v, p, INV_AT, p[1]) ** p[1]


@lru_cache(maxsize=64)
def _inverse_params(p: float) -> np.ndarray:
    """The inverse's block for a = 1/p: lnΓ(a), lnΓ(a + 1), (z₀, dz) of the P table
    (z = ln u on [ln INV_U_MIN, ln ½]) and of the Q table (z = ln(−ln v) on
    [ln ln 2, INV_ZQ_MAX]), then each table's cubic coefficients (4 × (INV_NODES − 1),
    Horner order as in lambda_table.py) of y = ln x, slopes exact from the density:
    dy/dz = u/(x P'(x)) and v (−ln v)/(x P'(x)), P'(x) = x^{a−1} e^{−x}/Γ(a)."""
    a = 1.0 / p
    lg = float(gammaln(a))
    zp = np.linspace(math.log(INV_U_MIN), math.log(0.5), INV_NODES)
    zq = np.linspace(math.log(math.log(2.0)), INV_ZQ_MAX, INV_NODES)
    u = np.exp(zp)
    v = np.exp(-np.exp(zq))
    xp, xq = gammaincinv(a, u), gammainccinv(a, v)
    yp, yq = np.log(xp), np.log(xq)
    # ln(x P'(x)) = a ln x − x − lnΓ(a)
    sp = np.exp(zp - (a * yp - xp - lg))
    sq = np.exp(np.log(v) + zq - (a * yq - xq - lg))
    cp = CubicHermiteSpline(zp, yp, sp).c
    cq = CubicHermiteSpline(zq, yq, sq).c
    out = np.concatenate([[lg, float(gammaln(a + 1.0)), zp[0], zp[1] - zp[0], zq[0], zq[1] - zq[0]],
                          cp.ravel(), cq.ravel()])
    out.flags.writeable = False
    return out


def _inverse(q: np.ndarray, u, v, a: float) -> np.ndarray:
    """x with P(a, x) = u (Q(a, x) = v = 1 − u) for the block ``q`` of a: the numpy form
    of :func:`inverse_scalar`, operation for operation."""
    u, v = np.broadcast_arrays(np.asarray(u, dtype=float), np.asarray(v, dtype=float))
    lg, lg1, zp0, dzp, zq0, dzq = q[:INV_HEADER]
    n = INV_NODES - 1
    cp = q[INV_HEADER:INV_HEADER + 4 * n].reshape(4, n)
    cq = q[INV_HEADER + 4 * n:INV_HEADER + 8 * n].reshape(4, n)
    lower = u <= 0.5
    w = np.where(lower, u, v)
    ok = w > 0
    with np.errstate(divide="ignore", invalid="ignore", over="ignore", under="ignore"):
        lw = np.log(np.where(ok, w, 0.5))
        z = np.where(lower, lw, np.log(-lw))
        z0, dz = np.where(lower, zp0, zq0), np.where(lower, dzp, dzq)
        i = np.clip(np.floor((z - z0) / dz), 0.0, n - 1.0).astype(np.intp)
        t = np.clip(z - (z0 + i * dz), 0.0, dz)
        c = np.where(lower, cp[:, i], cq[:, i])
        y = ((c[0] * t + c[1]) * t + c[2]) * t + c[3]
        y = np.where(lower & (z < z0), (lw + lg1) / a, y)
        x0 = np.exp(y)
        f = np.where(lower, gammainc(a, x0) - u, v - gammaincc(a, x0))
        dens = np.exp((a - 1.0) * y - x0 - lg)          # P'(x₀), y = ln x₀
        step = f / dens
        x1 = x0 - step / (1.0 - 0.5 * step * ((a - 1.0) / x0 - 1.0))
        x = np.where(dens > 0.0, np.where((x1 > 0.0) & np.isfinite(x1), x1, x0), x0)
    return np.where(ok, x, np.where(lower, 0.0, np.inf))


@scalar
def inverse_scalar(u, v, q, at, a):
    """x with P(a, x) = u, Q(a, x) = v (u + v = 1; the smaller one is solved for): a
    guess from the block ``q[at:]`` (see _inverse_params), then one Halley step
    x ← x − δ/(1 − δ f''/(2 f')), δ = f/f' (Gil, Segura & Temme 2012, sec. 4), kept
    where the density underflows (only at v ≲ 1e-300)."""
    lg, lg1 = q[at], q[at + 1]
    n = INV_NODES - 1
    lower = u <= 0.5
    w = u if lower else v
    if not w > 0.0:
        return 0.0 if lower else math.inf
    lw = math.log(w)
    if lower:
        z0, dz, c, z = q[at + 2], q[at + 3], at + INV_HEADER, lw
    else:
        z0, dz, c, z = q[at + 4], q[at + 5], at + INV_HEADER + 4 * n, math.log(-lw)
    if lower and z < z0:
        y = (lw + lg1) / a
    else:
        i = int(min(max(math.floor((z - z0) / dz), 0.0), n - 1.0))
        t = min(max(z - (z0 + i * dz), 0.0), dz)
        y = ((q[c + i] * t + q[c + n + i]) * t + q[c + 2 * n + i]) * t + q[c + 3 * n + i]
    x0 = math.exp(y)
    f = gammainc(a, x0) - u if lower else v - gammaincc(a, x0)
    dens = math.exp((a - 1.0) * y - x0 - lg)          # P'(x₀), y = ln x₀
    if not dens > 0.0:
        return x0
    step = f / dens
    x1 = x0 - step / (1.0 - 0.5 * step * ((a - 1.0) / x0 - 1.0))
    return x1 if x1 > 0.0 and math.isfinite(x1) else x0
