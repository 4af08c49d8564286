"""The identities of MATH.md (1–4, 6, 7) computed numerically for one model and one view
direction v, each next to the value it must have, with its error estimate and cost.

Rows (``ROW_IDS``; a request may ask for a subset):

* ``1``  ∫_{H²} D(m)(n·m) dm = 1                         (Heitz 2014, eq. 4)
* ``2``  ∫_{S²} D(m)(v·m) dm = n·v, signed                (Heitz 2014, eq. 5)
* ``3``  ∫ G1(v,m) D(m)(v·m)⁺ dm = n·v                    (Heitz 2014, eq. 43: Smith's G1)
* ``4``  ∫_{S²} D(h) G1(v)/(4|n·v|) dl = 1                (weak white furnace, Heitz 2014 sec. 5)
* ``7``  E(μ) ≤ 1, single scattering, F = 1               (Kulla & Conty 2017)
* ``7-loss``     1 − E_sep(μ) ≥ 1 − E_hc(μ): the separable G2 loses more energy than the
  height-correlated one (identity 6, integrated; Heitz 2014 eq. 98, 99)
* ``7-furnace``  E(μ) = 1 with F = 1 and Kulla-Conty compensation (Kulla & Conty 2017)

Quadrature for rows 1–4 (the integrals over m)
----------------------------------------------
Variables (r̃, ψ): m ∝ (X, Y, 1) with slopes (X, Y) = (α_x cosψ, α_y sinψ) r̃, so that
r̃ is the α-stretched slope radius of m and ψ its stretched azimuth (Heitz 2014 sec. 5).
However peaked D is (α = 1e-4) and however anisotropic (α_x/α_y = 1e4), its mass then
sits at r̃ ~ 1 for every ψ. dm = (n·m)³ dX dY (Heitz 2014 eq. 15), dX dY = α_x α_y r̃ dr̃ dψ.
r̃ = tanβ with β in two halves of N Gauss nodes: [0, β*/2] (the peak) and [β*/2, β*]
(the tail; where it is unbounded, β* = π/2, r̃ = cot ε with ε = π/2 − β = (π/4) u^k,
k > 1 only for tails heavier than GGX's: tail_k). ψ is cut at the axes and, for the
integrands with (v·m)⁺, where b(ψ) = α_x v_x cosψ + α_y v_y sinψ changes sign; there
the ray ends at the curve v·m = 0, r̃* = μ_v/(−b(ψ)) where b < 0, and ψ is graded
towards the cut (_psi_rule). On every piece the integrand is smooth and Gauss-Legendre
(N ψ × 2N r̃ nodes a piece) converges fast. This rule is written from the definitions
and uses neither the NDF's radial CDF nor its Λ: the identities test D and Λ, not the
code that samples or tabulates them.

Row 4 integrates over l with l's own area element. Its nodes are the images
l = 2(v·m)m − v of the nodes of row 3 (so they sit on the peak of D(h)), but the area
element of l is |∂l/∂r̃ × ∂l/∂ψ| dr̃ dψ, from the derivatives of the map (r̃, ψ) → l by
the chain rule (checked against mpmath in the tests), and D is evaluated at
h = (l+v)/‖l+v‖ recomputed from l. The Jacobian dl/dh = 4(v·h) (Walter et al. 2007,
eq. 14), on which the identity rests, is thus not assumed. l whose h is below the horizon
or faces away from v have D(h) = 0 and contribute nothing: the sphere of l is covered.

Error: the rule of order N is compared with 2N (_refine): ERROR_SAFETY × |I_2N − I_N|,
or a geometric-series estimate where successive differences shrink slowly, plus a
rounding floor, is reported as the error of I_2N; N doubles from ORDER_START while that
is above TARGET_ERROR (up to ORDER_MAX, and while the request's time budget affords it).

Rows 7: the deterministic albedo quadrature (integrate/albedo.py, via methods.albedo_by)
with its error bound, on the model rebuilt with fresnel=none, kd=0 (make_spec).

References
----------
Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
JCGT 3(2); Walter et al. 2007, "Microfacet Models for Refraction through Rough Surfaces";
Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks".
"""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass

import numpy as np

from ..integrate import budget
from ..integrate.methods import albedo_by
from ..errors import ParameterError
from ..model import COMMON_PARAMS, OPTIONS, ModelSpec, choice_params, make_spec
from ..physics.brdf import BRDF
from ..physics.g2 import G2_FORMS
from ..physics.gauss import gauss_legendre_01
from ..physics.masking import G1
from ..physics.vectors import direction_deg, half_vector

ROW_IDS = ("1", "2", "3", "4", "7", "7-loss", "7-furnace")

#: Gauss nodes per ψ piece (and per half of the r̃ range) of the first level; each level
#: doubles them. With the default shapes the error of rows 1–4 at N = 32 was ≤ 2e-8 and
#: at 64 ≤ 1e-14 for every NDF, α ∈ {1e-4, 0.05, 1} and α = (0.05, 0.5), θ = 60°.
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
#: θ from 0 to 89.9°, against MATH.md's closed forms): true error ≤ 0.32 × reported, but
#: for Blinn-Phong at α = 1e-4 (see ROUNDING_FLOOR).
ERROR_SAFETY = 2.0
#: Added to every error, relative to Σ|terms| of the sum: ~10⁵ terms, each with relative
#: rounding ~1e-16, and D evaluated at directions rounded to 1e-16 on a peak of width
#: α = 1e-4: two levels agreeing to 1e-15 do not make the sum exact to 1e-15 (seen:
#: 3e-14 at N = 16, GGX α = 1e-4, row 4). Not covered: an NDF whose D amplifies the
#: rounding of m itself (Blinn-Phong D = m_z^{α_p}, α_p = 2e8 at α = 1e-4: rows 1, 2
#: off by 6e-9) — HOLD_TOLERANCE is above it.
ROUNDING_FLOOR = 1e-13
#: Row 4 evaluates D at h = (l+v)/‖l+v‖: l + v cancels, so h's components carry absolute
#: rounding ~ε = 2.2e-16 where the peak of D has width α, and D's relative error per term
#: is up to ~2 r̃ ε/α (r̃ ≲ 5 where the mass is): this many ε/α_min is added to its floor
#: (seen: 1.5e-12 for Beckmann α = 1e-4 at θ = 89.9°, against a floor of 7e-13).
H_ROUNDING_EPS = 10.0
#: Row 4 leaves out nodes with (v·m) m_z below this: there h = (l+v)/‖l+v‖ has lost
#: more than 1e-7 of its relative accuracy in h_z (l + v cancels to ~4e-16 absolute).
H_MIN = 1e-8
#: The part row 4 leaves out is bounded by this many times its weight at the rule's own
#: nodes there: beyond the last node (r̃ ~ 1e58) a tail falling like r̃^{−0.04} (Student-t,
#: γ = 1.52) still holds as much again (seen: 2 % above 1×). Below γ ~ 1.7 row 4 is
#: then inconclusive: its error is of the order of its value.
DROPPED_SAFETY = 2.0
#: A row holds when |value − expected| ≤ error + HOLD_TOLERANCE (one-sided for ≤ / ≥).
#: Above every exact computation here: the tabulated Smith Λ (GTR, exponential power) is
#: within 1e-8 in G1 (physics/smith_table.py; measured 4e-9 in row 3 at α = 1); far below
#: every approximation the rows are meant to expose (Walter's Λ: ~1e-4 and more where it
#: differs from Beckmann's at all, Schlick-GGX ~1e-2).
HOLD_TOLERANCE = 1e-7
#: Quadrature tolerance of the albedo rows. 1e-7 (the API's smallest) took exponential
#: power at α = 1:1e-4, θ = 89.9° to 0.45 s a call (bench/checks.py), 1e-6 to 0.2 s; what
#: these rows compare is 1e-3 to 1e-1 apart (energy lost, separable against
#: height-correlated) or within the Kulla-Conty table's error (~2e-5). The reported error
#: is the quadrature's, whatever it reached (1.3e-6 at its highest order for α = 1e-4:1).
ALBEDO_TOL = 1e-6
#: Seconds each albedo of the rows 7 may refine for (a time budget of its own, inside the
#: request's): the quadrature stops before a level that would not fit, with its honest,
#: larger error and a note. Most models need a few ms; an anisotropic model with
#: masking=smith_numeric (a 192-node integral per μΛ) took 7–11 s per albedo to reach
#: tol. With at most three albedos (rows 7, 7-loss), a call stays under ~0.5 s.
ALBEDO_SECONDS = 0.15


@dataclass
class Row:
    id: str
    identity: str
    relation: str          # "=", "≤" or "≥": how value compares with expected
    value: float | None
    expected: float
    error: float | None    # estimated numerical error of value
    difference: float | None
    holds: bool | None     # None: the row does not apply to this model (see note)
    note: str
    evaluations: int
    seconds: float


IDENTITIES = {
    "1": ("∫ D(m)(n·m) dm = 1", "="),
    "2": ("∫_S² D(m)(v·m) dm = n·v", "="),
    "3": ("∫ G1(v,m) D(m)(v·m)⁺ dm = n·v", "="),
    "4": ("∫_S² D(h) G1(v)/(4|n·v|) dl = 1", "="),
    "7": ("E(μ) ≤ 1  (F = 1, single scattering)", "≤"),
    "7-loss": ("1 − E_sep(μ) ≥ 1 − E_hc(μ)  (F = 1)", "≥"),
    "7-furnace": ("E(μ) = 1  (F = 1, Kulla-Conty)", "="),
}


def holds(relation: str, difference: float, error: float) -> bool | None:
    """Whether the row holds; None where the quadrature did not converge (error inf):
    the check is then inconclusive, not passed."""
    if not np.isfinite(error):
        return None
    slack = error + HOLD_TOLERANCE
    if relation == "≤":
        return bool(difference <= slack)
    if relation == "≥":
        return bool(difference >= -slack)
    return bool(abs(difference) <= slack)


# ----------------------------------------------------------------- the rule over m

def _m_of(ax, ay, r, psi):
    """m ∝ (X, Y, 1) at stretched slope radius r̃ = r and stretched azimuth ψ:
    (X, Y) = (α_x cosψ, α_y sinψ) r̃."""
    X, Y = ax * r * np.cos(psi), ay * r * np.sin(psi)
    inv = 1.0 / np.sqrt(1.0 + X * X + Y * Y)
    return np.stack([X * inv, Y * inv, inv], axis=-1)


@dataclass
class _Rule:
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


def _psi_rule(ax: float, ay: float, v: np.ndarray, n: int, visible: bool):
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


def _rule(ax: float, ay: float, v: np.ndarray, n: int, visible: bool, k: float = 1.0) -> _Rule:
    """Nodes over the hemisphere of m (``visible``: only v·m ≥ 0), see the module doc;
    ``k`` the tail map's power (tail_k)."""
    psi, w_psi, b = _psi_rule(ax, ay, v, n, visible)
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
    m = _m_of(ax, ay, r, psi2)
    # dω_m = dX dY (n·m)³ (Heitz 2014 eq. 15: D (n·m) dω_m = P22 dX dY, P22 = D (n·m)⁴),
    # dX dY = α_x α_y r̃ dr̃ dψ.
    jac = ax * ay * r * m[..., 2] ** 3
    return _Rule(r.ravel(), psi2.ravel(), weight.ravel(), m.reshape(-1, 3), (weight * jac).ravel())


def _l_area(ax: float, ay: float, v: np.ndarray, rule: _Rule) -> tuple[np.ndarray, np.ndarray]:
    """l = 2(v·m)m − v at the nodes and its area element |∂l/∂r̃ × ∂l/∂ψ| per dr̃ dψ, by
    the chain rule through m = s/‖s‖, s = (X, Y, 1):
    ∂m = (∂s − m (m·∂s))/‖s‖, ∂l = 2(v·∂m) m + 2(v·m) ∂m, with
    ∂s/∂r̃ = (α_x cosψ, α_y sinψ, 0) and ∂s/∂ψ = (−α_x sinψ, α_y cosψ, 0) r̃."""
    mx, my, mz = rule.m[:, 0], rule.m[:, 1], rule.m[:, 2]     # m_z = 1/‖s‖
    cp, sp, r = np.cos(rule.psi), np.sin(rule.psi), rule.r
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
    l = 2.0 * vm[:, None] * rule.m - v
    return l, area


# ------------------------------------------------------------ adaptive refinement

@dataclass
class _Integral:
    value: float
    error: float
    evaluations: int
    order: int
    note: str = ""


def _refine(level, floor: float = ROUNDING_FLOOR) -> _Integral:
    """``level(n) -> (value, Σ|terms|, evaluations, bound of a part left out)``:
    compare n with 2n, doubling n
    while the error is above TARGET_ERROR, ORDER_MAX allows it, and the time budget
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
        if error <= TARGET_ERROR or 2 * n >= ORDER_MAX:
            return _Integral(fine, error, evaluations, 2 * n)
        b = budget.current()
        if b is not None and not b.affords(4.0 * last_seconds):
            note = f"stopped at order {2 * n} to end within the time budget"
            b.cut(f"checks: {note}")
            return _Integral(fine, error, evaluations, 2 * n, note)
        coarse, previous, n = fine, delta, 2 * n


# --------------------------------------------------------------------- the rows

def _view(theta_deg: float, phi_deg: float) -> np.ndarray:
    return direction_deg(theta_deg, phi_deg)


def _masking_kind(brdf: BRDF) -> str:
    """'exact' where G1 is the NDF's own Smith G1, else 'approximate'."""
    name = brdf.masking.name
    if name == "smith_numeric" or (name == "smith" and type(brdf.ndf).smith_exact):
        return "exact"
    return "approximate"


def _masking_note(brdf: BRDF) -> str:
    """Whether Smith's identities (3, 4) can hold with this masking, first clause first
    (the figure shows it under a row that fails)."""
    name = brdf.masking.name
    if _masking_kind(brdf) == "exact":
        return (f"masking={name} is Smith's exact Λ: G1(v) = n·v / ∫ D(m)(v·m)⁺ dm "
                f"(Heitz 2014, eq. 43)")
    if name == "smith":
        return (f"ndf={brdf.ndf.name}'s Λ is approximate (Walter's Beckmann substitution); "
                "Smith's identity holds only for the NDF's own Λ (masking=smith_numeric)")
    return (f"masking={name} approximates Smith's Λ; the identity holds only for the NDF's "
            "own Λ, so the difference is the approximation's error")


def _lobe_note(brdf: BRDF) -> str:
    return (f"; for the first lobe's D (α = {brdf.ndf.alpha_x:g}), the second obeys it alike"
            if brdf.lobe2 is not None and brdf.lobe_mix > 0 else "")


def _quadrature_row(rid: str, brdf: BRDF, v: np.ndarray, expected: float, note: str) -> Row:
    ndf = brdf.ndf
    ax, ay = ndf.alpha_x, ndf.alpha_y
    t0 = time.perf_counter()
    mu_v = float(v[2])
    g1 = 1.0
    if rid in ("3", "4"):
        g1 = float(G1(v[2], brdf.masking.mu_Lambda(ndf, v)))

    k = tail_k(ndf)

    def level(n):
        rule = _rule(ax, ay, v, n, visible=rid in ("3", "4"), k=k)
        dropped = 0.0
        if rid == "1":
            terms = ndf.D(rule.m) * rule.m[:, 2] * rule.dm
        elif rid == "2":
            terms = ndf.D(rule.m) * (rule.m @ v) * rule.dm
        elif rid == "3":
            terms = ndf.D(rule.m) * np.maximum(rule.m @ v, 0.0) * rule.dm
        else:
            l, area = _l_area(ax, ay, v, rule)
            h, exists = half_vector(l, v)
            # l + v = 2(v·m) m is formed by cancellation: h_z keeps ~4e-16/(2(v·m) m_z)
            # relative accuracy, none where (v·m) m_z ≲ 1e-16 (the far tail, reached by
            # the tail map: m_z down to 1e-70). Nodes below H_MIN are left out and their
            # share bounded by what they weigh in row 3's sum (×4: dl = 4(v·m) dm there).
            vm = np.maximum(rule.m @ v, 0.0)
            keep = exists & (vm * rule.m[:, 2] > H_MIN)
            D = np.zeros(rule.size)
            D[keep] = ndf.D(h[keep])
            terms = D * area * rule.weight
            dropped = DROPPED_SAFETY * 4.0 * float(np.sum(np.where(keep, 0.0, ndf.D(rule.m) * vm * rule.dm)))
        return float(np.sum(terms)), float(np.sum(np.abs(terms))), rule.size, dropped

    floor = ROUNDING_FLOOR
    if rid == "4":
        floor += H_ROUNDING_EPS * np.finfo(float).eps / min(ax, ay)
    res = _refine(level, floor)
    scale = {"1": 1.0, "2": 1.0, "3": g1, "4": g1 / (4.0 * mu_v) if mu_v > 0 else 0.0}[rid]
    value, error = scale * res.value, abs(scale) * res.error
    identity, relation = IDENTITIES[rid]
    diff = value - expected
    note = f"{note}; Gauss order {res.order} vs {res.order // 2}" + _lobe_note(brdf)
    if res.note:
        note += f"; {res.note}"
    return Row(rid, identity, relation, value, expected, error, diff, holds(relation, diff, error),
               note, res.evaluations, time.perf_counter() - t0)


# ------------------------------------------------------------- the albedo rows

def model_values(spec: ModelSpec, **overrides) -> dict:
    """Flat parameters of ``spec`` (as make_spec takes them) with ``overrides``: the
    roughness resolved to α (no roughness/anisotropy form), derived values dropped, and
    the parameters of a replaced choice (Schlick's f0 when fresnel changes; λ(φ) when
    the new G2 does not take it) left out."""
    v = spec.values
    out = {name: v[name] for name in OPTIONS}
    for p in COMMON_PARAMS:
        if p.name not in ("roughness", "anisotropy") and v.get(p.name) is not None:
            out[p.name] = v[p.name]
    out.update(overrides)
    for option in ("ndf", "fresnel"):
        if out[option] == v[option]:
            for p in choice_params(option, v[option]):
                if v.get(p.name) is not None:
                    out[p.name] = v[p.name]
    g2 = G2_FORMS[out["g2"]]
    if g2.needs_phi and v.get("lambda_phi") is not None:
        out["lambda_phi"] = v["lambda_phi"]
    return out


class _Albedos:
    """E(μ) of variants of the model with F = 1, kd = 0, each computed at most once."""

    def __init__(self, spec: ModelSpec, mu: float, phi: float):
        self.spec, self.mu, self.phi = spec, mu, phi
        self.done: dict[tuple, dict] = {}

    def get(self, **overrides) -> tuple[dict, int]:
        """(albedo_by's result, its evaluations if computed now, else 0: a row that
        reuses another row's albedo does not count its cost twice)."""
        key = tuple(sorted(overrides.items()))
        if key in self.done:
            return self.done[key], 0
        spec = make_spec(**model_values(self.spec, fresnel="none", kd=0.0, **overrides))
        outer = budget.current()
        seconds = ALBEDO_SECONDS
        if outer is not None:
            seconds = max(0.0, min(seconds, outer.seconds - outer.elapsed()))
        with budget.limit(seconds) as own:
            res = albedo_by(spec.brdf(), [self.mu], self.phi, method="quadrature",
                            tol=ALBEDO_TOL, average=False)
        if own.notes:
            res = dict(res, cut=(f"albedo stopped before reaching tol {ALBEDO_TOL:g}: this view "
                                 f"gives each albedo {seconds:.2g} s (ALBEDO_SECONDS in "
                                 "app/checks.py, or what the request's budget had left)"))
            if outer is not None and seconds < ALBEDO_SECONDS:
                outer.cut(f"checks: {res['cut']}")
        self.done[key] = res
        return res, int(res["evaluations"])


def _albedo_row(rid: str, brdf: BRDF, spec: ModelSpec, albedos: _Albedos) -> Row:
    t0 = time.perf_counter()
    identity, relation = IDENTITIES[rid]
    g2 = spec.values["g2"]
    if rid == "7":
        r, evaluations = albedos.get(multiscatter="none", g2=g2)
        value, error, expected = float(r["E"][0]), float(r["E_error"][0]), 1.0
        note = (f"g2={g2}, masking={spec.values['masking']}, fresnel=none, kd=0, no compensation: "
                f"the single-scattering albedo loses {1.0 - value:.3g} of the energy")
        if value > 1.0 + error + HOLD_TOLERANCE:
            note = f"E > 1: this model creates energy; {_masking_note(brdf)}; " + note
        if "cut" in r:
            note += f"; {r['cut']}"
    elif rid == "7-loss":
        sep, ev_sep = albedos.get(multiscatter="none", g2="separable")
        hc, ev_hc = albedos.get(multiscatter="none", g2="height_correlated")
        value, expected = 1.0 - float(sep["E"][0]), 1.0 - float(hc["E"][0])
        error = float(sep["E_error"][0] + hc["E_error"][0])
        evaluations = ev_sep + ev_hc
        note = (f"value: energy lost with the separable G2, expected: with the height-correlated "
                f"one (masking={spec.values['masking']}); G1(l)G1(v) ≤ 1/(1 + Λ(l) + Λ(v)) "
                "(identity 6): the separable form shadows more")
        if ev_hc == 0 or ev_sep == 0:
            note += "; one of the two albedos is row 7's, computed once (its cost counted there)"
        for cut in {x["cut"] for x in (sep, hc) if "cut" in x}:
            note += f"; {cut}"
    else:
        return _furnace_row(brdf, spec, albedos, t0)
    diff = value - expected
    return Row(rid, identity, relation, value, expected, error, diff, holds(relation, diff, error),
               note, int(evaluations), time.perf_counter() - t0)


def furnace_refusal(brdf: BRDF, spec: ModelSpec) -> str | None:
    """Why the compensated furnace does not apply to this model, or None."""
    if not brdf.ndf.isotropic:
        return ("does not apply to anisotropic roughness; Kulla-Conty compensation is for "
                "isotropic roughness only (its E(μ, α) table is isotropic)")
    if _masking_kind(brdf) != "exact":
        return ("does not apply with an approximate Λ; compensation needs the exact Smith Λ "
                f"(its table and the albedo it compensates): {_masking_note(brdf)}")
    if spec.values.get("multiscatter") != "kulla_conty":
        return ("not computed: set multiscatter=kulla_conty to run it; the model's E(μ, α) "
                "table, which takes 1–25 s to build (GGX 0.9 s, direction-correlated G2 "
                "25 s), is built then, as for every view of that model, and this row costs "
                "a millisecond")
    return None


def _furnace_row(brdf: BRDF, spec: ModelSpec, albedos: _Albedos, t0: float) -> Row:
    identity, relation = IDENTITIES["7-furnace"]
    why = furnace_refusal(brdf, spec)
    if why is not None:
        return Row("7-furnace", identity, relation, None, 1.0, None, None, None, why, 0,
                   time.perf_counter() - t0)
    try:
        r, evaluations = albedos.get(multiscatter="kulla_conty")
    except ParameterError as exc:      # a combination make_spec refuses: say why
        return Row("7-furnace", identity, relation, None, 1.0, None, None, None,
                   f"does not apply; {exc.message}", 0, time.perf_counter() - t0)
    value = float(r["E"][0])
    error = float(r["E_single_error"][0]) + float(r["compensation_error"])
    diff = value - 1.0
    note = (f"E = E_single {float(r['E_single'][0]):.6f} + E_ms {value - float(r['E_single'][0]):.6f}; "
            f"error = quadrature + the E(μ, α) table's measured error "
            f"{float(r['compensation_error']):.1e}")
    if "cut" in r:
        note += f"; {r['cut']}"
    return Row("7-furnace", identity, relation, value, 1.0, error, diff, holds(relation, diff, error),
               note, evaluations, time.perf_counter() - t0)


# ------------------------------------------------------------------------ entry

def check_rows(spec: ModelSpec, theta_deg: float = 60.0, phi_deg: float = 0.0,
               ids=None) -> list[Row]:
    """The rows ``ids`` (default all, in ROW_IDS order) for the model and the view
    direction v at (θ, φ) in degrees, θ ∈ [0, 90)."""
    wanted = [r for r in ROW_IDS if ids is None or r in set(ids)]
    brdf = spec.brdf()
    brdf = brdf.single() if hasattr(brdf, "single") else brdf
    v = _view(theta_deg, phi_deg)
    mu = float(v[2])
    albedos = _Albedos(spec, mu, float(np.deg2rad(phi_deg)))
    notes = {
        "1": "D is normalised (MATH.md conventions)",
        "2": "signed projected area: the facets facing away from v count negatively",
        "3": _masking_note(brdf),
        "4": "weak white furnace, over l with l's own area element",
    }
    if _masking_kind(brdf) != "exact":     # the reason these rows fail comes first
        notes["4"] = f"{_masking_note(brdf)}; {notes['4']}"
    expected = {"1": 1.0, "2": mu, "3": mu, "4": 1.0}
    rows = []
    for rid in wanted:
        if rid in expected:
            rows.append(_quadrature_row(rid, brdf, v, expected[rid], notes[rid]))
        else:
            rows.append(_albedo_row(rid, brdf, spec, albedos))
    return rows


def checks(spec: ModelSpec, theta_deg: float = 60.0, phi_deg: float = 0.0, ids=None) -> dict:
    """The rows as columns (one list per field, equal lengths: what the CSV export
    writes; each row's seconds in ``seconds_by_row``) plus the view direction, the
    tolerance and the totals."""
    t0 = time.perf_counter()
    rows = check_rows(spec, theta_deg, phi_deg, ids)
    # One list per field, the seconds apart (keyed by row): the lists are the table's
    # columns, which the CSV export writes (the numeric ones) and its test compares with
    # the JSON of another request, and a time is not the same twice.
    columns = {f: [asdict(r)[f] for r in rows] for f in Row.__dataclass_fields__ if f != "seconds"}
    b = budget.current()
    # row_order: the ids as one line of text, so that a CSV export (which writes the
    # numeric lists only) still says which row is which.
    out = {**columns, "row_order": ", ".join(r.id for r in rows),
           "theta_deg": float(theta_deg), "phi_deg": float(phi_deg),
           "mu": float(_view(theta_deg, phi_deg)[2]), "hold_tolerance": HOLD_TOLERANCE,
           "seconds_by_row": {r.id: r.seconds for r in rows},
           "total_evaluations": int(sum(r.evaluations for r in rows)),
           "total_seconds": time.perf_counter() - t0,
           "complete": not (b and b.notes)}
    if not out["complete"]:
        out["budget_note"] = "; ".join(b.notes) + " (setting BRDF_MAX_SECONDS)"
    return out
