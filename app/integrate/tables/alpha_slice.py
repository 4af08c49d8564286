"""E(μ) of one lobe at one roughness α, interpolated on nodes placed where E changes fast.

Kulla-Conty's compensation needs E(μ) at the lobe's own α only (and its Ē); a whole
E(μ, α) table (table.py) answers every α but its error is one number for all of them and
its build is ~56 rows of this. Here, for one α: E at the nodes of y = √a/(1 + √a)
(Smith's a = 1/(α tanθ), table.py's axis: 1 − E ~ y² ln y at grazing) by the reference
quadrature (albedo.py), a not-a-knot cubic spline through them, and every cell checked at
its quarter points (CHECK_AT) against the quadrature there; a cell whose miss (× SAFETY,
+ the nodes' own quadrature error) is above GOAL is halved — its midpoint becomes a node —
and the new spline is checked again in every cell, until every cell passes. For
Student-t below γ = 2 the axis is x = y^q (grazing_exponent), where E is smooth, and
below MU_TAIL its nodes take E's grazing asymptote 1 − A μ^q (grazing_tail), computed in
logs: the quadrature does not reach μ < 1e-150, nor μ below the smallest double, where E
still falls for γ near 1.5. Heavy tails and grazing μ get more nodes, light ones stay at
the first grid.

``error`` = SAFETY × the largest check-point miss of the final spline + the largest node
error: a bound on |Ê − E| at every μ (a cubic spline's error in a cell peaks near its
middle; tests/integrate/test_alpha_slice.py checks it at points between the midpoints and
the nodes, against an independent quadrature). Ē is the spline's own average, so the
Kulla-Conty lobe built on it has albedo exactly 1 − Ê(μ) (docs/kulla_conty.md §3).
(derivation and measurements: docs/tables.md §5)

References: Kulla & Conty 2017 (E(μ) per α); de Boor 1978, A Practical Guide to Splines,
ch. IV (not-a-knot cubic interpolation, its O(h⁴) error)."""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np
from scipy.interpolate import CubicSpline

from ...physics.gauss import gauss_legendre_01
from ..albedo import albedo
from ...physics.numeric import where_valid
from ..cache import complete_only
from .table import E_AVG_NODES_PER_CELL, Y_GRADING, lobe_at, mu_from_y, y_from_mu

#: Largest reported error a slice is refined to: below the 1e-4 the API promises for
#: compensation (issue 37).
GOAL = 8e-5
#: Reported error = SAFETY × the largest check-point miss + the node error (module docstring).
#: Measured against an independent dense check (quarter and tenth points of every cell,
#: quadrature at tol 1e-7; GGX, Beckmann, Blinn-Phong, GTR γ 0.5-1.5, α 0.05-1): the true
#: error was up to 5.3× the midpoint miss (GGX α = 0.05: 2.4e-5 against 4.5e-6), so 2
#: was not a bound; 8 is.
SAFETY = 8.0
#: Where each cell is checked (fractions of it): two points, not the midpoint alone. A
#: midpoint can sit near a zero of the cell's error: Student-t γ = 1000, α = 0.37 missed
#: by 4.0e-5 at μ = 0.61 where the largest midpoint miss was 5.1e-6 (stated 4.1e-5).
CHECK_AT = (0.25, 0.75)
#: Quadrature tolerance of each node: an eighth of GOAL (it adds to the bound directly).
NODE_TOL = 3e-6
#: First grid: FIRST_CELLS cells of y = (k/FIRST_CELLS)^Y_GRADING (table.py's grading).
FIRST_CELLS = 16
#: Halvings at most, and nodes at most: a slice that has not met GOAL by then reports
#: what it has (its error says so). 40 rounds, not 6: for Student-t near γ = 1.5, the
#: bulk of E (μ ≳ 1e-6) lies in a band of width ~q at x → 1, which the halvings reach
#: from the first grid's first cell (γ = 1.501: 10 rounds, 55 nodes at α = 0.05); a round
#: that halves one cell costs the quadrature at three μ.
MAX_ROUNDS = 40
MAX_NODES = 257
#: Slices kept per process (each a few kB).
CACHE_SIZE = 512
#: Below this μ, for a slice whose axis has q < 1 (Student-t below γ = 2), E is not
#: computed by quadrature but from its grazing asymptote E = 1 − A μ^q, A from the
#: quadrature at MU_TAIL itself (docs/tables.md §5): the next term is O(μ) (measured:
#: (1 − E)/μ^q constant to 1e-10 from μ = 1e-10 to 1e-150 at γ = 1.51 and 1.55), and the
#: quadrature's disk radius ~1/μ overflows float64 below μ ≈ 1e-150, where E still
#: falls for γ < 1.52 (and below μ = 5e-324 for γ < 1.5007: unrepresentable μ, which
#: the asymptote reaches in logs through x).
MU_TAIL = 1e-100
#: Where the asymptote is checked against the quadrature (its miss enters the error).
MU_TAIL_CHECK = 1e-140


@dataclass(frozen=True, eq=False)   # hashed by identity
class ESlice:
    key: tuple               # table.table_key of the lobe (F = 1)
    alpha: float             # the roughness this slice is for
    y: np.ndarray            # nodes, in x = y^q (grazing_exponent)
    values: np.ndarray       # E at the nodes
    spline: CubicSpline      # in x = y^q (a piecewise cubic: spline.x, spline.c)
    error: float             # bound on |Ê − E| at every μ (module docstring)
    measured: float          # largest check-point miss of the final spline
    node_error: float
    E_avg_value: float       # 2 ∫ Ê μ dμ of the spline itself
    build_seconds: float
    build_evaluations: int
    exponent: float = 1.0    # q of the axis x = y^q (grazing_exponent)
    base = None              # not a Schlick-basis table (compensation reads E directly)

    @property
    def size(self) -> str:
        return f"{self.y.size} μ at α = {self.alpha:g}"

    def E(self, mu, alpha: float | None = None) -> np.ndarray:
        """Ê(μ) at this slice's α (another α is refused: it is not in the slice),
        clipped to [0, 1] (docs/identities.md §7)."""
        if alpha is not None and float(alpha) != self.alpha:
            raise ValueError(f"this E(μ) slice is for α = {self.alpha:g}, not {float(alpha):g}")
        return np.clip(self.spline(self.x_from_mu(mu)), 0.0, 1.0)

    def x_from_mu(self, mu) -> np.ndarray:
        """The spline's variable x = y(μ)^q (y: table.y_from_mu at this α)."""
        y = y_from_mu(np.clip(np.asarray(mu, dtype=float), 0.0, 1.0), self.alpha)
        return y if self.exponent == 1.0 else y ** self.exponent

    def E_avg(self, alpha: float | None = None) -> float:
        if alpha is not None and float(alpha) != self.alpha:
            raise ValueError(f"this E(μ) slice is for α = {self.alpha:g}, not {float(alpha):g}")
        return self.E_avg_value


def grazing_exponent(ndf) -> float:
    """q of the slice's axis x = y^q: 1 − E(μ) ~ μ^q at grazing for a tail whose r̃ grows
    like v^{−β} with β > ½ (``tail_beta``; Student-t at γ < 2: q = 1/β − 1 = 2γ − 3),
    so E is smooth in x (1 − E ~ x², as in y for GGX: y² ln y); q = 1 (x = y) for every
    tail up to GGX's. Measured (Student-t, α = 0.37): 1 − E(μ) from μ = 1e-30 to 1e-20
    grows ×10.0 at γ = 1.55 (q = 0.1), ×40 from 1e-20 to 1e-12 at γ = 1.6 (q = 0.2)."""
    beta = float(ndf.tail_beta)
    return 1.0 if beta <= 0.5 else min(1.0, 1.0 / beta - 1.0)


def _mu_from_x(x, alpha: float, q: float):
    return mu_from_y(np.asarray(x, dtype=float) ** (1.0 / q), alpha)


def _E_avg(x_nodes: np.ndarray, alpha: float, q: float, E) -> float:
    """2 ∫₀¹ E(μ) μ dμ by Gauss-Legendre in y on every cell of the nodes' y = x^{1/q}, μ = μ(y).
    In y, not x: for q below ~1e-12 the cells near x = 1 are a few ulps wide, and Gauss
    nodes inside them round (Ē came out 3e-3 for E ≈ 1e-15 at γ = 1.5 + 1 ulp); in y
    they are distinct cells, or none (nodes rounding to the same y hold no μ)."""
    t, w = gauss_legendre_01(E_AVG_NODES_PER_CELL)
    y_nodes = np.unique(x_nodes ** (1.0 / q))
    lo, hi = y_nodes[:-1, None], y_nodes[1:, None]
    y = (lo + (hi - lo) * t).ravel()
    wy = ((hi - lo) * w).ravel()
    mu = mu_from_y(y, alpha)
    # dμ/dy = 2αy (1 − y)³ / ((1 − y)⁴ + α²y⁴)^{3/2}: table.mu_from_y differentiated, in
    # the form that stays finite as y → 1
    dmu = 2.0 * alpha * y * (1.0 - y) ** 3 / ((1.0 - y) ** 4 + (alpha * y * y) ** 2) ** 1.5
    return float(2.0 * np.sum(E(mu) * mu * dmu * wy))


def _log_mu_from_x(x, alpha: float, q: float):
    """ln μ at x = y^q, computed in logs (μ underflows for y below ~1e-162, and x = y^q
    reaches such y at x ~ 1e-162^q, well inside [0, 1] for small q): −inf at x = 0."""
    x = np.asarray(x, dtype=float)

    def positive(x):
        ln_y = np.log(x) / q
        y = np.exp(ln_y)
        ln_aa = 2.0 * (ln_y - np.log1p(-y)) + np.log(alpha)     # aa = a α (mu_from_y)
        return ln_aa - 0.5 * np.logaddexp(0.0, 2.0 * ln_aa)     # μ = aa/√(1 + aa²)
    return where_valid((x > 0) & (x < 1), [x], positive, np.where(x > 0, 0.0, -np.inf))


@dataclass(frozen=True)
class GrazingTail:
    """E = 1 − A μ^q below MU_TAIL (docs/tables.md §5): A from the quadrature at MU_TAIL,
    ``error`` bounds its miss below MU_TAIL (that node's error, plus the miss and the
    node error at MU_TAIL_CHECK)."""
    A: float
    q: float
    error: float
    evaluations: int

    def E(self, log_mu):
        return 1.0 - self.A * np.exp(self.q * np.asarray(log_mu, dtype=float))


def grazing_tail(lobe, q: float) -> GrazingTail:
    """Fit A at MU_TAIL and check the asymptote at MU_TAIL_CHECK (one quadrature call).
    The error below MU_TAIL: with E = 1 − A_true μ^q + r(μ), r = O(μ), the fitted A is off
    by (δ + r(MU_TAIL))/MU_TAIL^q, δ the node's quadrature error, so Ê is off by at most
    (δ + |r(MU_TAIL)|)(μ/MU_TAIL)^q + |r(μ)| ≤ δ + 2 |r(MU_TAIL)|; the check's miss
    (with its own node error) stands for r."""
    res = albedo(lobe, np.array([MU_TAIL, MU_TAIL_CHECK]), tol=NODE_TOL)
    A = (1.0 - float(res.E[0])) / MU_TAIL ** q
    tail = GrazingTail(A, q, 0.0, res.evaluations)
    miss = abs(float(res.E[1]) - float(tail.E(np.log(MU_TAIL_CHECK))))
    error = float(res.E_error[0]) + 2.0 * (miss + float(res.E_error[1]))
    return GrazingTail(A, q, error, res.evaluations)


def build(key: tuple, alpha: float) -> ESlice:
    """Refine until every cell's bound meets GOAL (module docstring)."""
    t0 = time.perf_counter()
    lobe = lobe_at(key, alpha)
    q = grazing_exponent(lobe.ndf)
    known: dict[float, tuple[float, float]] = {}     # x → (E, its quadrature error)
    tail = grazing_tail(lobe, q) if q < 1.0 else None
    evaluations = 0 if tail is None else tail.evaluations

    def compute(xs):
        nonlocal evaluations
        new = np.array(sorted({float(v) for v in xs} - known.keys()))
        if not new.size:
            return
        if tail is not None:
            log_mu = _log_mu_from_x(new, alpha, q)
            deep = log_mu < np.log(MU_TAIL)
            known.update(zip(new[deep].tolist(), ((e, tail.error) for e in tail.E(log_mu[deep]).tolist())))
            new = new[~deep]
        if new.size:
            res = albedo(lobe, _mu_from_x(new, alpha, q), tol=NODE_TOL)
            evaluations += res.evaluations
            known.update(zip(new.tolist(), zip(res.E.tolist(), res.E_error.tolist())))

    # the first grid: table.py's y nodes (the same μ for every q)
    # (unique: for q below ~1e-15, at γ within a few ulps of 1.5, the last nodes round to 1)
    x = np.unique((np.linspace(0.0, 1.0, FIRST_CELLS + 1) ** Y_GRADING) ** q)
    for round_ in range(MAX_ROUNDS + 1):
        h = np.diff(x)
        checks = np.concatenate([x[:-1] + CHECK_AT[0] * h, x[:-1] + CHECK_AT[1] * h])
        compute(np.concatenate([x, checks]))    # one quadrature call per round
        values = np.array([known[v][0] for v in x.tolist()])
        spline = CubicSpline(x, values, bc_type="not-a-knot")
        cell_miss = np.abs(spline(checks) - np.array([known[v][0] for v in checks.tolist()]))
        miss = np.maximum(cell_miss[:h.size], cell_miss[h.size:])
        node_error = max(e for _, e in known.values())
        bad = SAFETY * miss + node_error > GOAL
        if not bad.any() or round_ == MAX_ROUNDS or x.size + bad.sum() > MAX_NODES:
            break     # x, values and spline stay those just checked
        x = np.unique(np.concatenate([x, 0.5 * (x[:-1] + x[1:])[bad]]))   # a cell one ulp wide stays
    measured = float(np.max(miss))
    E_avg = _E_avg(x, alpha, q, lambda m: np.clip(spline(y_from_mu(m, alpha) ** q), 0.0, 1.0))
    return ESlice(key, alpha, x, values, spline, SAFETY * measured + node_error, measured,
                  node_error, E_avg, time.perf_counter() - t0, evaluations, q)


@complete_only(CACHE_SIZE, complete=lambda s: s.error <= GOAL)
def slice_for_key(key: tuple, alpha: float) -> ESlice:
    """The (cached) slice of ``key`` at ``alpha``. A slice the request's time budget cut
    short, or that did not meet GOAL, is answered, not kept."""
    return build(key, float(alpha))
