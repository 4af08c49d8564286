"""The albedo quadrature's ψ nodes and tail power (used by albedo.py's _integrate_order).

ψ: the two quarters either side of the horizon cut, graded towards it (_psi_quarters);
the u-rule's tail map power k by the NDF's tail (tail_k); the measurements that chose
each are beside it. The grading is slope_quadrature.psi_rule's.

References: Heitz 2014, JCGT 3(2) (Smith's a = 1/(α tanθ)).
"""
from __future__ import annotations

import numpy as np

from ..physics.gauss import gauss_legendre_01

#: Cap on the tail substitution power (see physics/smith_integral.K_MAX).
TAIL_K_MAX = 24.0
# Smallest grading scale g of the ψ rule (_psi_quarters): below a ~ 1e-3 the feature at
# the horizon cut carries little (plain nodes: error 2e-8 at N = 24, a = 3e-4), and log
# spacing down to g spreads the nodes over ln(π/2g) for nothing. Measured (GGX, Beckmann,
# α = 0.01 to 1, a = 3e-5 to 1e-2, N = 24): worst error 8e-6 with g = a, 1e-7 with a floor
# of 1e-3, 3e-7 (Beckmann, α = 1, a ~ 5e-3; GGX 8e-9) with 3e-3; 1e-2 is worse at N = 48.
PSI_GRADING_MIN = 3e-3
# Tail power for tails shorter than GGX's (tail_k). Measured (Beckmann, α = 0.01 to 1,
# μ with a = 0.005 to 0.2, graded ψ): k = 2 converges like N⁻⁴ in u (6e-8 at N = 48,
# 4e-9 at 96: ρ̃² = −k ln(1 − s) puts a logarithm at s = 1); k = 4: ≤ 9e-9 at 48,
# ≤ 3e-12 at 96; k = 6 and 8 the same as 4.
TAIL_K_SHORT = 4.0


def tail_k(beta: float) -> float:
    """Power k of the u-rule's tail map 1 − u ∝ (1 − s)^k (_u_rule) for an NDF whose
    r̃ grows like v^{−β} (``tail_beta``). GGX's β = ½: k = 2, r̃ ∝ (1 − s)^{−1}, and at
    v_z = 0 integrand·du is a series in integer powers of 1 − s. Shorter tails (β < ½):
    TAIL_K_SHORT. Longer: 2/(1 − β), so that integrand·du vanishes at s = 1."""
    if beta > 0.5:
        return min(2.0 / (1.0 - beta), TAIL_K_MAX)
    return 2.0 if beta == 0.5 else TAIL_K_SHORT


def _graded(n: int, g):
    """d = |ψ − π/2| and weights (rows, n) of n Gauss nodes on [0, π/2], even in ln(g + d)."""
    t, wt = gauss_legendre_01(n)
    L = np.log1p(0.5 * np.pi / g)
    return g * np.expm1(t * L), g * L * np.exp(t * L) * wt


def _psi_quarters(n: int, mu, B, short_tail: bool = False):
    """ψ − ψ0 offsets and weights (rows, 2n) of the two quarters [0, π/2] and [π/2, π],
    n Gauss nodes each, graded towards the horizon cut π/2 (where b = 0): there the
    disk's exit radius changes from ~1/α to ≫ 1 over |ψ − π/2| ~ g = μ/B (B = α sinθ,
    g = Smith's a = 1/(α tanθ)), a feature Gauss nodes reach only at n ~ 1/√g: with
    d = |ψ − π/2| = g (e^{tL} − 1), L = ln(1 + (π/2)/g), nodes are evenly spaced in
    ln(g + d) (as slope_quadrature.psi_rule; Heitz 2014's a). Measured (GGX, α = 0.01
    to 1, μ with a = 0.005 to 0.01): error at N = 48 from ~1e-6 to ≤ 5e-10. g is at least
    PSI_GRADING_MIN; plain nodes where it is 0 (μ = 0: the half-plane, smooth) or not
    finite (μ = 1). Short tails: SHORT_SPLIT."""
    mu = np.asarray(mu, dtype=float)
    with np.errstate(divide="ignore", invalid="ignore"):
        g, c = mu / np.asarray(B, dtype=float), mu / np.sqrt(1.0 - mu * mu)
    graded = ((g > 0) & np.isfinite(g))[:, None]
    gg = np.where(graded, np.maximum(g[:, None], PSI_GRADING_MIN), 1.0)
    d, dd = _graded(n, gg)
    offsets, w = np.concatenate([0.5 * np.pi - d, 0.5 * np.pi + d], 1), 2.0 * np.concatenate([dd, dd], 1)
    if short_tail:
        share, scale, a_min, c_max = SHORT_SPLIT
        d1, dd1 = _graded(int(round(share * n)), scale * gg)
        d2, dd2 = _graded(2 * n - int(round(share * n)), gg)
        split = graded & (gg >= a_min) & (c[:, None] <= c_max)
        offsets = np.where(split, np.concatenate([0.5 * np.pi - d1, 0.5 * np.pi + d2], 1), offsets)
        w = np.where(split, 2.0 * np.concatenate([dd1, dd2], 1), w)
    t, wt = gauss_legendre_01(n)
    plain = np.concatenate([t, t + 1.0]) * (np.pi / 2), np.concatenate([wt, wt]) * np.pi
    return np.where(graded, offsets, plain[0]), np.where(graded, w, plain[1])


# Short tails (β < ½) at a ≥ a_min and μ/sinθ ≤ c_max: the quarter facing the view (b > 0)
# holds the turn-on of the mass inside the disk (R ~ 1-3 at |ψ − ψ_cut| ~ a/6 to a/2), the
# other is smooth there. (share of the 2n nodes on b > 0, its scale / g, a_min, c_max).
# Measured (Beckmann, 32² build): entries at order 96 205 → 67, evaluations 5.7e6 → 4.5e6,
# the same bound and dense check; a share of 1.5, a_min 0.05 or c_max 0.3 sent more to 96.
SHORT_SPLIT = (4.0 / 3.0, 0.3, 0.1, 0.1)
