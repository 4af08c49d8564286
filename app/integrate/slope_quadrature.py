"""Quadrature over microfacet normals m in α-stretched slope space, for any roughness
and anisotropy: nodes (``rule``) over the hemisphere of m, or over the part v·m ≥ 0, and
the area element of l = 2(v·m)m − v (``l_area``) for integrals over l; ``refine`` doubles
the order until its error estimate is small. Written from the definitions alone (it uses
neither an NDF's radial CDF nor its Λ), so it can test them. Derivation:
docs/slope_quadrature.md (§1 variables, §2 integrals over l, §3 error).

References: Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based
BRDFs", JCGT 3(2); Walter et al. 2007, "Microfacet Models for Refraction through Rough
Surfaces".
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..physics.gauss import gauss_legendre_01
from . import budget

#: Gauss nodes per ψ piece (and per half of the r̃ range) of the first level; each level
#: doubles them. With the default shapes the error of the identity checks (rows 1–4) at
#: N = 32 was ≤ 2e-8 and at 64 ≤ 1e-14 for every NDF, α ∈ {1e-4, 0.05, 1} and α = (0.05, 0.5), θ = 60°.
ORDER_START = 16
#: Highest order: 6 ψ pieces × N ψ nodes × 2N β nodes, 196 608 at N = 128, ~60 ms a row.
ORDER_MAX = 128
#: Above this ratio of successive differences Δ_2N/Δ_N the convergence is algebraic,
#: not geometric, and the error left is estimated as a geometric series (_refine). Gauss-
#: Legendre on a smooth integrand gives ratios ≤ 0.1; an end-point singularity ε^a
#: gives 2^{−(2a+2)}, 0.5 at a = −½.
RATE_SLOW = 0.25
#: Tail map (tail_k): the end-point power it aims at, and its largest k (beyond, the
#: map's last nodes would sit at ε ~ (1/N²)^k, below what tan resolves). Student-t at
#: γ → 1.5, where the mean slope and Λ diverge, is then resolved only slowly; the error
#: estimate above says so.
TAIL_POWER = 2.0
TAIL_K_MAX = 12.0
#: Differences below this many rounding floors are noise: their ratio says nothing.
RATE_NOISE = 100.0
#: Stop refining when the reported error is below this (far below any tolerance here:
#: the rule converges geometrically, the next level costs 4× the last).
TARGET_ERROR = 1e-11
#: Reported error = ERROR_SAFETY × |I_2N − I_N| + the rounding floor below. |I_2N − I_N|
#: is about the error of I_N, which Gauss-Legendre's geometric convergence makes far
#: larger than that of I_2N; the factor covers pre-asymptotic levels. Measured with the
#: order capped at 32, 64, 128 (every NDF, α from 1e-4 to 1 and three anisotropic pairs,
#: θ from 0 to 89.9°, against the NDFs' closed forms): true error ≤ 0.32 × reported, but
#: for Blinn-Phong at α = 1e-4 (see ROUNDING_FLOOR).
ERROR_SAFETY = 2.0
#: Added to every error, relative to Σ|terms| of the sum: ~10⁵ terms, each with relative
#: rounding ~1e-16, and D evaluated at directions rounded to 1e-16 on a peak of width
#: α = 1e-4: two levels agreeing to 1e-15 do not make the sum exact to 1e-15 (seen:
#: 3e-14 at N = 16, GGX α = 1e-4, row 4). Not covered: an NDF whose D amplifies the
#: rounding of m itself (Blinn-Phong D = m_z^{α_p}, α_p = 2e8 at α = 1e-4: rows 1, 2
#: off by 6e-9); the checks' HOLD_TOLERANCE is above it.
ROUNDING_FLOOR = 1e-13


def m_of(ax, ay, r, psi):
    """m ∝ (X, Y, 1) at stretched slope radius r̃ = r and stretched azimuth ψ:
    (X, Y) = (α_x cosψ, α_y sinψ) r̃."""
    X, Y = ax * r * np.cos(psi), ay * r * np.sin(psi)
    inv = 1.0 / np.sqrt(1.0 + X * X + Y * Y)
    return np.stack([X * inv, Y * inv, inv], axis=-1)


@dataclass
class Rule:
    r: np.ndarray        # (K,) stretched slope radius r̃ of each node
    psi: np.ndarray      # stretched azimuth ψ
    weight: np.ndarray   # dr̃ dψ weights
    m: np.ndarray        # (K, 3)
    dm: np.ndarray       # ∫ g dm ≈ Σ g(m) dm

    @property
    def size(self) -> int:
        return self.r.size


def tail_k(ndf) -> float:
    """Power k of the tail map for an NDF whose tail mass falls like r̃^{−1/β_t}
    (``tail_beta``): in ε = π/2 − β the first-moment integrand of rows 2–4 then behaves
    like ε^{1/β_t − 3} dε, singular for β_t > ½ (Student-t with γ < 2), and with
    ε ∝ u^k like u^{k(1/β_t − 1) − 1} du: k makes that power TAIL_POWER, at most
    TAIL_K_MAX. 1 (no map) for tails up to GGX's, where the integrand is smooth."""
    beta_t = float(getattr(ndf, "tail_beta", 0.0))
    if beta_t <= 0.5:
        return 1.0
    return min(TAIL_K_MAX, (1.0 + TAIL_POWER) / (1.0 / beta_t - 1.0))


def psi_rule(ax: float, ay: float, v: np.ndarray, n: int, visible: bool):
    """ψ nodes and weights over [0, 2π), and B, b(ψ) of v·m ∝ v_z + r̃ b(ψ)."""
    # b = α_x v_x cosψ + α_y v_y sinψ = B cos(ψ − ψ_v).
    bx, by = ax * v[0], ay * v[1]
    B = float(np.hypot(bx, by))
    cuts = [0.0, 0.5 * np.pi, np.pi, 1.5 * np.pi]
    horizon = []                 # where b = 0: the curve v·m = 0 reaches the horizon
    if visible and B > 0:
        pv = np.arctan2(by, bx)
        horizon = [np.mod(pv + 0.5 * np.pi, 2 * np.pi), np.mod(pv - 0.5 * np.pi, 2 * np.pi)]
    # Rounded, so that a cut computed at 90° and the axis at 90° merge instead of
    # leaving a piece 1e-16 wide.
    horizon = np.round(np.asarray(horizon), 12)
    cuts = np.unique(np.concatenate([np.round(np.asarray(cuts), 12), horizon]))
    cuts = np.append(cuts, cuts[0] + 2 * np.pi)
    t, w = gauss_legendre_01(n)
    lo, hi = cuts[:-1, None], cuts[1:, None]
    # Next to a horizon cut ψ_c, β* = atan(μ_v/(B |cos(ψ − ψ_c ∓ π/2)|)) climbs from ~0 to
    # π/2 over |ψ − ψ_c| ~ μ_v/B (= Smith's a = 1/(α tanθ)): at grazing v and α ~ 1 a
    # feature 1e-3 wide, which plain Gauss nodes reach only at N ~ 1/√(1e-3) per piece
    # (seen: |I_128 − I_64| = 1e-11 with I_128 still 1.2e-10 off, Beckmann α = 1,
    # θ = 89.9°). There ψ is graded geometrically towards the cut:
    # |ψ − ψ_c| = g (e^{tL} − 1), L = ln(1 + len/g), g = μ_v/B: nodes evenly spaced in
    # ln(g + |ψ − ψ_c|), which resolves the feature at every scale; for g ≳ len it is
    # close to the plain rule.
    length = hi - lo
    at_lo = np.isin(lo, horizon)
    at_hi = np.isin(hi, horizon) | np.isin(hi - 2 * np.pi, horizon)
    psi, w_psi = lo + length * t, length * w
    if (at_lo.any() or at_hi.any()) and v[2] > 0:       # g = μ_v/B finite and > 0
        g = v[2] / B
        L = np.log1p(length / g)
        d = g * np.expm1(t[None, :] * L)
        dd = g * L * np.exp(t[None, :] * L) * w[None, :]
        psi = np.where(at_lo, lo + d, np.where(at_hi, hi - d, psi))
        w_psi = np.where(at_lo | at_hi, dd, w_psi)
    psi, w_psi = psi.ravel(), w_psi.ravel()
    return psi, w_psi, bx * np.cos(psi) + by * np.sin(psi)


def rule(ax: float, ay: float, v: np.ndarray, n: int, visible: bool, k: float = 1.0) -> Rule:
    """Nodes over the hemisphere of m (``visible``: only v·m ≥ 0), see the module doc;
    ``k`` the tail map's power (tail_k)."""
    psi, w_psi, b = psi_rule(ax, ay, v, n, visible)
    t, w = gauss_legendre_01(n)
    t, w = t[None, :], w[None, :]
    # β = atan r̃ in two halves of N nodes each: [0, β*/2] holds the peak of D (r̃ ≤ 1
    # when β* = π/2), [β*/2, β*] the tail; β* = atan(μ_v/(−b)) where v·m = 0 cuts the
    # ray (visible rows, b < 0), else π/2. An unbounded tail is parametrised by
    # ε = π/2 − β = (π/4) u^k, u = 1 − t (k = tail_k, 1 for tails up to GGX's), and
    # r̃ = cot ε computed from ε: through β, r̃ would stop at tan(π/2 rounded) = 1.6e16,
    # where a tail falling like r̃^{−0.1} (Student-t, γ = 1.55) still holds 2 % of row 3.
    behind = visible & (b < 0)
    beta_max = np.where(behind, np.arctan2(v[2], np.where(behind, -b, 1.0)), 0.5 * np.pi)[:, None]
    half = 0.5 * beta_max
    beta1 = half * t
    r1 = np.tan(beta1)
    dr1 = (1.0 + r1 * r1) * half * w                 # dr̃ = dβ / cos²β
    beta2 = half + half * t
    r2 = np.tan(beta2)
    dr2 = (1.0 + r2 * r2) * half * w
    u = 1.0 - t
    eps = 0.25 * np.pi * u ** k
    r_tail = 1.0 / np.tan(eps)
    dr_tail = (1.0 + r_tail * r_tail) * 0.25 * np.pi * k * u ** (k - 1.0) * w
    unbounded = ~behind[:, None]
    r2 = np.where(unbounded, r_tail, r2)
    dr2 = np.where(unbounded, dr_tail, dr2)
    r = np.concatenate([r1, r2], axis=1)
    weight = np.concatenate([dr1, dr2], axis=1) * w_psi[:, None]
    psi2 = np.broadcast_to(psi[:, None], r.shape)
    m = m_of(ax, ay, r, psi2)
    # dω_m = dX dY (n·m)³ (Heitz 2014 eq. 15: D (n·m) dω_m = P22 dX dY, P22 = D (n·m)⁴),
    # dX dY = α_x α_y r̃ dr̃ dψ.
    jac = ax * ay * r * m[..., 2] ** 3
    return Rule(r.ravel(), psi2.ravel(), weight.ravel(), m.reshape(-1, 3), (weight * jac).ravel())


def l_area(ax: float, ay: float, v: np.ndarray, nodes: Rule) -> tuple[np.ndarray, np.ndarray]:
    """l = 2(v·m)m − v at the nodes and its area element |∂l/∂r̃ × ∂l/∂ψ| per dr̃ dψ, by
    the chain rule through m = s/‖s‖, s = (X, Y, 1):
    ∂m = (∂s − m (m·∂s))/‖s‖, ∂l = 2(v·∂m) m + 2(v·m) ∂m, with
    ∂s/∂r̃ = (α_x cosψ, α_y sinψ, 0) and ∂s/∂ψ = (−α_x sinψ, α_y cosψ, 0) r̃."""
    mx, my, mz = nodes.m[:, 0], nodes.m[:, 1], nodes.m[:, 2]     # m_z = 1/‖s‖
    cp, sp, r = np.cos(nodes.psi), np.sin(nodes.psi), nodes.r
    vm = v[0] * mx + v[1] * my + v[2] * mz

    def dl(sx, sy):
        """∂l for ∂s = (sx, sy, 0), as three component arrays."""
        proj = mx * sx + my * sy
        dmx, dmy, dmz = (sx - mx * proj) * mz, (sy - my * proj) * mz, -mz * proj * mz
        vdm = v[0] * dmx + v[1] * dmy + v[2] * dmz
        return (2.0 * (vdm * mx + vm * dmx), 2.0 * (vdm * my + vm * dmy), 2.0 * (vdm * mz + vm * dmz))

    ax_, ay_, az_ = dl(ax * cp, ay * sp)
    bx_, by_, bz_ = dl(-ax * sp * r, ay * cp * r)
    area = np.sqrt((ay_ * bz_ - az_ * by_) ** 2 + (az_ * bx_ - ax_ * bz_) ** 2
                   + (ax_ * by_ - ay_ * bx_) ** 2)
    l = 2.0 * vm[:, None] * nodes.m - v
    return l, area


# ------------------------------------------------------------ adaptive refinement

@dataclass
class Integral:
    value: float
    error: float
    evaluations: int
    order: int
    note: str = ""


def refine(level, floor: float = ROUNDING_FLOOR, label: str = "quadrature",
           target: float = TARGET_ERROR) -> Integral:
    """``level(n) -> (value, Σ|terms|, evaluations, bound of a part left out)``:
    compare n with 2n, doubling n
    while the error is above ``target``, ORDER_MAX allows it, and the time budget
    affords the next level (predicted at 4× the last: N² nodes a piece).

    Error of I_2N: ERROR_SAFETY × Δ, Δ = |I_2N − I_N|, or — where the last two
    differences say the convergence is slow (ρ = Δ/Δ_previous > RATE_SLOW: an integrable
    singularity at the end of the β range that the map did not remove) — the rest of a
    geometric series, Δ ρ/(1 − ρ); inf (not converged) for ρ ≥ 1. Plus ``floor`` ×
    Σ|terms| (rounding)."""
    n = ORDER_START
    coarse, _, evaluations, _ = level(n)
    previous = None
    while True:
        t0 = time.perf_counter()
        fine, magnitude, ev, dropped = level(2 * n)
        last_seconds = time.perf_counter() - t0
        evaluations += ev
        delta, rounding = abs(fine - coarse), floor * magnitude
        error = ERROR_SAFETY * delta
        if previous is not None and previous > RATE_NOISE * rounding and delta > rounding:
            rate = delta / previous
            if rate >= 1.0:
                error = np.inf
            elif rate > RATE_SLOW:
                error = max(error, delta * rate / (1.0 - rate))
        error += rounding + dropped
        if error <= target or 2 * n >= ORDER_MAX:
            return Integral(fine, error, evaluations, 2 * n)
        b = budget.current()
        if b is not None and not b.affords(4.0 * last_seconds):
            note = f"stopped at order {2 * n} to end within the time budget"
            b.cut(f"{label}: {note}")
            return Integral(fine, error, evaluations, 2 * n, note)
        coarse, previous, n = fine, delta, 2 * n

