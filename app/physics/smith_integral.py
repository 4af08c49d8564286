"""The general Smith masking integral, by quadrature, for any slope-space NDF.

G1(ω) = μ / A(ω) with A(ω) = ∫ D(m) (ω·m)⁺ dm (Heitz 2014, eq. 43), so μΛ = A − μ. In
α-stretched slopes, with a = μ/s and s = α(φ) sinθ, that is one integral over the NDF's
radial CDF u = C(r̃):

    μΛ = (s/π) ∫_{C(a)}^{1} [ √(r̃² − a²) − a·atan(√(r̃² − a²)/a) ] du,   r̃ = C⁻¹(u),

i.e. Λ(a) = (1/a)∫_a^∞ (x − a) g(x) dx (docs/conventions.md §5). It is integrated over the
tail mass v = 1 − u ∈ (0, 1 − C(a)] (``radial_ccdf``, exact where it is 1e-300), with a
substitution graded by ``tail_beta`` so that the integrand vanishes at the end for every
tail; μΛ = 0 where that mass underflows. It is the reference the Λ table (smith_table.py)
is built from (which imports this module, never the reverse: the tabulated μΛ,
``smith_table.mu_Lambda_smith_numeric``, is the table's); tests/physics/test_smith_integral.py
checks it against every closed form.
(derivation: docs/smith.md §1, §2)
"""
from __future__ import annotations

import numpy as np

from .gauss import gauss_legendre_01
from .numeric import where_valid

# Gauss points of the reference rule. |ΔG1| against the closed forms: 3e-15 (GGX),
# 1e-10 (Beckmann), ≤ 1e-6 for Student-t down to γ = 1.525, where Λ(45°) ≈ 1.4 and
# diverging (tests/physics/test_zoo.py).
ORDER = 192
# Cap on the substitution power: (1 − t)^k at the last Gauss node (1 − t ≈ 1e-10 at order
# 384) stays far above underflow for k ≤ 12. Only Student-t with γ < 1.545 asks for
# more; there Λ is heading to infinity and the reference loses accuracy (see the test).
K_MAX = 12.0


def mu_Lambda_quadrature(ndf, w, order: int = ORDER) -> np.ndarray:
    """μΛ(ω) by the general Smith integral, directly; ``ndf`` is a SlopeSpaceNDF."""
    w = np.asarray(w, dtype=float)
    mu = w[..., 2]
    s = ndf.stretched_sin(w)
    v0 = where_valid((mu >= 0) & (s > 0), [mu, s], lambda m, ss: ndf.radial_ccdf((m / ss) ** 2), 0.0)
    return where_valid(v0 > 0, [mu, s, v0], lambda m, ss, v: _integral(ndf, m, ss, v, order), 0.0)


def h_and_slope(ndf, a, order: int = ORDER) -> tuple[np.ndarray, np.ndarray]:
    """h(a) = μΛ/s and its derivative dh/da at a > 0 (see :func:`h_derivatives`)."""
    return h_derivatives(ndf, a, order)[:2]


def h_derivatives(ndf, a, order: int = ORDER) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
    """h(a) = μΛ/s, dh/da and d²h/da² at a > 0, for the table (smith_table.py).

    Differentiating under the integral (the integrand vanishes at its lower end r̃ = a):
    d/da [q − a·atan(q/a)] = −atan(q/a) with q = √(r̃² − a²), so
    dh/da = −(1/π) ∫_{C(a)}^1 atan(q/a) du, and d/da atan(q/a) = −1/q, so
    d²h/da² = (1/π) ∫_{C(a)}^1 du/q: the marginal slope density g(a) (h = ∫_a^∞ (x − a)
    g(x) dx, Heitz 2014 eq. 72), at the same nodes as h. Near r̃ = a, q ∝ √t and the rule's
    dt ∝ √t dσ (:func:`t_rule`), so du/q is smooth in σ too."""
    a = np.asarray(a, dtype=float)
    v0 = ndf.radial_ccdf(a * a)
    h, slope, curvature = _integral(ndf, a, np.ones_like(a), v0, order, with_slope=True)
    return tuple(np.where(v0 > 0, x, 0.0) for x in (h, slope, curvature))


def t_rule(order: int = ORDER) -> tuple[np.ndarray, np.ndarray]:
    """(1 − t, dt) of the rule in t = sin²(πσ/2), σ Gauss-Legendre on [0, 1]: near t = 0
    (r̃ → a) the integrand starts like √(r̃² − a²) — at a = 0 like √(1 − v) — which a
    plain Gauss rule in t resolves only to third order (7e-8 at order 192, GGX grazing);
    in σ it is smooth (8e-13, measured). Shared with the compiled loop (app/kernels)."""
    sg, wsg = gauss_legendre_01(order)
    t = np.sin(0.5 * np.pi * sg) ** 2
    return 1.0 - t, 0.5 * np.pi * np.sin(np.pi * sg) * wsg


def tail_power(ndf) -> float:
    """k of the substitution v = v₀ (1 − t)^k (the integrand then vanishes at t = 1)."""
    return min(1.0 / (1.0 - ndf.tail_beta), K_MAX)


def _integral(ndf, mu, s, v0, order, with_slope: bool = False):
    a, v0 = (mu / s)[..., None], v0[..., None]
    one_minus_t, wt = t_rule(order)
    k = tail_power(ndf)
    v = v0 * one_minus_t ** k
    dv = k * v0 * one_minus_t ** (k - 1.0) * wt
    # Where v₀ (1 − t)^k underflows to 0 the node's weight dv is below 1e-308 too: it
    # contributes 0, and r̃ is not needed there.
    r2 = where_valid(v > 0, [v], ndf.radial_ccdf_inv, 0.0)
    q = np.sqrt(np.maximum(r2 - a * a, 0.0))
    angle = np.arctan2(q, a)
    value = s / np.pi * np.sum((q - a * angle) * dv, axis=-1)
    if not with_slope:
        return value
    # q = 0 only where rounding puts C⁻¹(v) at a² (v = v₀ to the last bits, or dv = 0):
    # that node's true term is ≤ ~1e-12 of the sum (tests/physics/test_smith_curvature.py)
    inv_q = where_valid(q > 0, [q], np.reciprocal, 0.0)
    return value, -np.sum(angle * dv, axis=-1) / np.pi, np.sum(inv_q * dv, axis=-1) / np.pi
