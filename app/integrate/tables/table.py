"""Tables of the directional albedo E(μ, α) of one single-scattering lobe, interpolated.

A table holds E at the nodes of a (r = √α, y) grid, y = √a/(1 + √a) with Smith's
a = 1/(α tanθ), each node computed by the quadrature of ``albedo.py``, for one NDF
(with its shape parameters), masking, G2 form and one Fresnel basis: F = 1 (Kulla &
Conty's compensation) or S = (1 − cos θ_d)^p, with which any Fresnel on the Schlick
basis (``Fresnel.schlick_basis``) is E = Σ c E_p. The S table holds the scaled
deviation from the mirror, (E_S − Ê₁(1 − μ)^p)/w(α). A bicubic spline interpolates;
its error is measured at off-grid check points when the table is built and reported
(``error``). Whole tables are kept, persisted and built outside requests by
store.py (which imports this module, never the reverse); anisotropic roughness is not tabulated.
(derivation and measurements: docs/tables.md §1–§3)

References: Kulla & Conty 2017, "Revisiting Physically Based Shading at Imageworks" (32×32
table of E(μ, r)); Heitz 2014 (a = 1/(α tanθ)); Dierckx 1993 (bicubic splines, FITPACK)."""
from __future__ import annotations

import time
import weakref
from dataclasses import dataclass, replace

import numpy as np
from scipy.interpolate import RectBivariateSpline

from ...physics.brdf import BRDF
from ...physics.fresnel import FRESNELS
from ...physics.gauss import gauss_legendre_01
from ...physics.numeric import where_valid
from ... import kernels
from .. import budget
from ..albedo import albedo

#: Smallest tabulated perceptual roughness: √(1e-4), the smallest α the API takes.
ROUGHNESS_MIN = 1e-2
#: Default grid (μ axis y, roughness axis r): the smallest whose reported bound is
#: ≤ 1e-5 for GGX (BENCHMARKS.md §2, "The interpolated table"; Kulla & Conty's 32² is 3e-5).
TABLE_N_Y = 56
TABLE_N_R = 56
#: Grid of a lobe built without compiled loops (numba absent or BRDF_FAST=0, loops not
#: ready, a component with no scalar formula): its numpy quadrature is ~10× slower, and a
#: 56² build (30 s for Student-t on numpy, measured) would not fit one request's time budget
#: (BRDF_MAX_SECONDS, 10 s), so every request would be cut short and rebuild it. 32²:
#: ~9 s; its bound (measured at build, ~3e-5 for GGX) is what the response reports.
SLOW_TABLE_N = 32
#: ... and when that one would not build within the request's budget (GTR at γ near 1.5:
#: ~13 s predicted), this coarser grid, reported with its own larger bound, before the
#: request is refused: a slider on a shape parameter then gets answers with
#: compensation on. Measured for GTR γ = 1.5, F = 1 (idle): 16² 2.4 s, bound 6.1e-3;
#: 24² 3.6 s, 3.5e-3. Kept for the process like any whole table (a precise one: the CLI,
#: which has no budget, or a raised BRDF_MAX_SECONDS in a fresh process).
COARSE_TABLE_N = 16
#: Quadrature tolerance of each node: 10× below the interpolation error of 64×64 tables
#: (the reported error adds the nodes' own estimated errors).
BUILD_TOL = 1e-6
#: Off-grid check points: CHECK_R + 2 roughness cells × every y cell.
CHECK_R = 8
#: y nodes are (k/(n−1))^Y_GRADING, denser near y = 0 (grazing), where 1 − E ~ y² ln y
#: at high roughness (measured slope 1.9 → 2 in log-log): a cubic spline on uniform y
#: missed it by 1.4e-4 at 32×32; graded 1.5 gives 3e-5 (2: 7e-5, finer at 0 but
#: coarser mid-range). Measured by a dense check (bench/table_sizes.py).
Y_GRADING = 1.5
#: Reported error = this × the largest deviation seen at the check points (which sample
#: the cells, they do not find the worst point of each) + the nodes' quadrature error.
TABLE_ERROR_SAFETY = 2.0
def build_points(n_y: int = TABLE_N_Y, n_r: int = TABLE_N_R) -> int:
    """E(μ) values one build computes by quadrature: the nodes and the check points."""
    return n_r * n_y + min(CHECK_R + 2, n_r - 1) * (n_y - 1)


#: Gauss nodes per y interval of the E_avg rule (the spline is a cubic there).
E_AVG_NODES_PER_CELL = 8
#: The Schlick-basis table's grid is the F = 1 table's with its first SCHLICK_SPLIT_R
#: r cells and its last SCHLICK_SPLIT_Y y cells split at their midpoints (module
#: docstring). Measured (GGX h-c, p = 5, 56×56, dense check): no split 1.5e-5 (worst at
#: α = 3e-4, μ = 0); first r cell 7.7e-6 (α = 5e-3, μ = 0.65); and the last 3 y cells
#: 5.9e-6 (α = 3e-2, μ = 0.7; splitting 6, 10 or 14 y cells: 5.5e-6 to 6.2e-6; the next
#: r cell too: 5.9e-6).
SCHLICK_SPLIT_R = 1
SCHLICK_SPLIT_Y = 3


def split_cells(nodes: np.ndarray, first: int = 0, last: int = 0) -> np.ndarray:
    """``nodes`` with their ``first`` first and ``last`` last cells split at the midpoint."""
    mids = 0.5 * (nodes[:-1] + nodes[1:])
    cell = np.arange(mids.size)
    return np.sort(np.concatenate([nodes, mids[(cell < first) | (cell >= mids.size - last)]]))


def mirror_scale(alpha):
    """w(α) = α (1 + ln(1/α)), the size of the Schlick basis' deviation from the mirror
    (module docstring); > 0 on (0, 1]."""
    alpha = np.asarray(alpha, dtype=float)
    return alpha * (1.0 - np.log(alpha))


def mu_from_y(y, alpha):
    """μ at y for roughness α: a = (y/(1 − y))², μ = aα/√(1 + (aα)²) (μ = 1 at y = 1)."""
    y = np.asarray(y, dtype=float)
    alpha = np.asarray(alpha, dtype=float)
    y, alpha = np.broadcast_arrays(y, alpha)
    return where_valid(y < 1.0, [y, alpha], _mu_finite, 1.0)


def _mu_finite(y, alpha):
    aa = (y / (1.0 - y)) ** 2 * alpha
    return aa / np.sqrt(1.0 + aa * aa)


def y_from_mu(mu, alpha):
    """Inverse of :func:`mu_from_y`: a = μ/(α sinθ), y = √a/(1 + √a) (y = 1 at μ = 1)."""
    mu = np.clip(np.asarray(mu, dtype=float), 0.0, 1.0)
    alpha = np.asarray(alpha, dtype=float)
    mu, alpha = np.broadcast_arrays(mu, alpha)

    def finite(m, al):
        root_a = np.sqrt(m / (al * np.sqrt((1.0 - m) * (1.0 + m))))
        return root_a / (1.0 + root_a)
    return where_valid(mu < 1.0, [mu, alpha], finite, 1.0)


def table_key(lobe: BRDF, basis_p: float | None = None) -> tuple:
    """What E of a single isotropic lobe depends on besides (μ, α): NDF class and shape,
    masking, G2 form, λ(φ), and the Fresnel basis (None: F = 1; p: Schlick basis)."""
    ndf = lobe.ndf
    shape = tuple((p.name, getattr(ndf, p.name)) for p in ndf.shape_params)
    return (type(ndf), shape, lobe.masking, lobe.g2, lobe.lambda_phi, basis_p)


@dataclass(frozen=True, eq=False)   # hashed by identity (a cache key)
class ETable:
    key: tuple
    r: np.ndarray            # roughness nodes √α
    y: np.ndarray            # y nodes
    values: np.ndarray       # E at (r, y), shape (len(r), len(y))
    spline: RectBivariateSpline
    error: float             # reported bound on |E_table − E| anywhere in the table
    measured: float          # largest deviation seen at the check points
    node_error: float        # largest quadrature error of a node
    build_seconds: float
    build_evaluations: int
    #: None: ``values`` are E on (r, y). A table (the F = 1 table of the same lobe):
    #: ``values`` are the Schlick basis' scaled deviation (E − Ê₁ (1 − μ)^p)/w(α) on
    #: base's (r, y) with split cells (see the module docstring).
    base: "ETable | None" = None

    @property
    def size(self) -> str:
        return f"{self.y.size}×{self.r.size}"

    def E(self, mu, alpha) -> np.ndarray:
        """Interpolated E(μ, α), clipped to [0, 1] (docs/identities.md §7)."""
        alpha = np.asarray(alpha, dtype=float)
        r = np.clip(np.sqrt(alpha), self.r[0], self.r[-1])
        mu = np.clip(np.asarray(mu, dtype=float), 0.0, 1.0)
        y = y_from_mu(mu, np.clip(alpha, self.r[0] ** 2, 1.0))
        r, y, mu = np.broadcast_arrays(r, y, mu)
        if self.base is not None:
            return np.clip(_schlick_from_table(self, r, y, mu, self.spline.ev(r, y)), 0.0, 1.0)
        return np.clip(self.spline.ev(r, y), 0.0, 1.0)

    def E_avg(self, alpha: float) -> float:
        """2 ∫₀¹ Ê(μ, α) μ dμ of the interpolant itself (so that the Kulla-Conty lobe
        built on Ê has albedo exactly 1 − Ê(μ)), by Gauss-Legendre in y on every interval
        of the y grid, μ = μ(y). Memoised per table, and dropped with it."""
        memo = _E_AVG.setdefault(self, {})
        if len(memo) > E_AVG_MEMO:
            memo.clear()
        if alpha not in memo:
            memo[alpha] = _E_avg(self, float(alpha))
        return memo[alpha]


#: E_avg by α of each live table, dropped with it (an lru_cache kept evicted tables alive)
_E_AVG: "weakref.WeakKeyDictionary[ETable, dict]" = weakref.WeakKeyDictionary()
E_AVG_MEMO = 256    # α values memoised per table at most


def _E_avg(table: ETable, alpha: float) -> float:
    t, w = gauss_legendre_01(E_AVG_NODES_PER_CELL)
    # on the table's y cells (the Schlick table's contain the F = 1 table's, whose
    # spline is part of its E)
    lo, hi = table.y[:-1, None], table.y[1:, None]
    y = (lo + (hi - lo) * t).ravel()
    wy = ((hi - lo) * w).ravel()
    al = max(alpha, table.r[0] ** 2)
    mu = mu_from_y(y, al)
    # dμ/dy: μ = aα/√(1 + a²α²), a = (y/(1−y))² → dμ/da = α/(1 + a²α²)^{3/2},
    # da/dy = 2y/(1 − y)³ (y < 1 at every Gauss node).
    a = (y / (1.0 - y)) ** 2
    dmu = al / (1.0 + (a * al) ** 2) ** 1.5 * 2.0 * y / (1.0 - y) ** 3
    return float(2.0 * np.sum(table.E(mu, alpha) * mu * dmu * wy))


def _basis_fresnel(basis_p):
    if basis_p is None:
        return FRESNELS["none"]()
    return FRESNELS["schlick"](f0=0.0, f90=1.0, fresnel_p=basis_p)


def lobe_at(key: tuple, alpha: float) -> BRDF:
    ndf_class, shape, masking, g2, lambda_phi, basis_p = key
    return BRDF(ndf_class(alpha, None, **dict(shape)), masking, g2, _basis_fresnel(basis_p),
                lambda_phi=lambda_phi)


class TableTooSlow(ValueError):
    """A table whose build, predicted from its first row, would not end within the
    request's time budget: refused (HTTP 422 naming ``param``) rather than left to
    run — a cut build still computes every row once, which took 108 s for GGX with
    masking=smith_numeric (the numeric Smith integral at every integrand point)."""
    param = "multiscatter"


def _refuse_if_too_slow(key: tuple, predicted: float) -> None:
    b = budget.current()
    if b is not None and not b.affords(predicted):
        ndf_class, _, masking, g2, _, _ = key
        raise TableTooSlow(
            f"the E(μ, α) table of ndf={ndf_class.name}, masking={masking.name}, g2={g2.name} "
            f"would take ~{predicted:.0f} s to build, beyond this request's time budget "
            f"(setting BRDF_MAX_SECONDS={b.seconds:g}); tables are fast for the compiled "
            "integrand (ggx, beckmann with masking=smith); outside the server (Python, the "
            "CLI) there is no budget")


def _mirror(base: ETable, p: float, r, y, mu):
    """Ê₁ (1 − μ)^p, the Schlick basis' mirror part, from the F = 1 table's spline
    (unclipped): the same at the nodes (where D is formed) and at lookup."""
    return base.spline.ev(r, y) * (1.0 - mu) ** p


def _schlick_from_table(table: ETable, r, y, mu, deviation):
    """E_S = D w(α) + Ê₁ (1 − μ)^p from the scaled deviation D at (r, y) (module
    docstring)."""
    return deviation * mirror_scale(r * r) + _mirror(table.base, table.key[-1], r, y, mu)


def _nodes(key: tuple, r: np.ndarray, y: np.ndarray, tol: float, base: ETable | None):
    """Values at the nodes (E, or the Schlick basis' scaled deviation D), evaluations,
    node error. D's nodes use the F = 1 spline Ê₁, so that the table gives E_S at its
    nodes whatever Ê₁'s own error: its node error is E_S's."""
    values = np.empty((r.size, y.size))
    evaluations, node_error = 0, 0.0
    t0 = time.perf_counter()
    for i, ri in enumerate(r):
        if i == 1:
            _refuse_if_too_slow(key, (time.perf_counter() - t0) * (r.size + CHECK_R + 1))
        alpha = ri * ri
        mu = mu_from_y(y, alpha)
        res = albedo(lobe_at(key, alpha), mu, tol=tol)
        evaluations += res.evaluations
        node_error = max(node_error, float(np.max(res.E_error)))
        if base is None:
            values[i] = res.E
            continue
        mirror = _mirror(base, key[-1], np.full(y.size, ri), y, mu)
        values[i] = (res.E - mirror) / mirror_scale(alpha)
    return values, evaluations, node_error


def build(key: tuple, n_y: int = TABLE_N_Y, n_r: int = TABLE_N_R, tol: float = BUILD_TOL,
          seed: int = 0, base: ETable | None = None) -> ETable:
    """Compute the nodes, fit the spline, measure its error (see the module docstring).
    With ``base`` (the F = 1 table of the same lobe) the table is the Schlick basis'
    scaled deviation on base's grid with split cells (n_y and n_r are not used). A
    node's quadrature error is part of the reported error, so a build that a request's
    time budget cut short reports the larger error it has."""
    t0 = time.perf_counter()
    if base is None:
        r = np.linspace(ROUGHNESS_MIN, 1.0, n_r)
        y = np.linspace(0.0, 1.0, n_y) ** Y_GRADING
    else:
        r = split_cells(base.r, first=SCHLICK_SPLIT_R)
        y = split_cells(base.y, last=SCHLICK_SPLIT_Y)
        n_y, n_r = y.size, r.size
    values, evaluations, node_error = _nodes(key, r, y, tol, base)
    spline = RectBivariateSpline(r, y, values, kx=3, ky=3, s=0)
    table = ETable(key, r, y, values, spline, 0.0, 0.0, node_error, 0.0, 0, base)
    # Check points: every y cell, in CHECK_R roughness cells (the first and the last
    # always: the grazing corner at r = 1 is where a 32×32 table was worst), each at
    # the cell's centre moved by a seeded jitter of up to ±40 % of the cell (never on a
    # node). Every y cell: a random subset of them missed that corner and the bound
    # came out 7× too small (bench/table_sizes.py's dense check found it).
    rng = np.random.default_rng(seed)
    inner = rng.choice(np.arange(1, n_r - 2), min(CHECK_R, n_r - 3), replace=False)
    ri = np.unique(np.concatenate([[0, n_r - 2], inner]))
    r_check = r[ri] + (0.5 + rng.uniform(-0.4, 0.4, ri.size)) * np.diff(r)[ri]
    measured = 0.0
    for rc in r_check:
        y_check = y[:-1] + (0.5 + rng.uniform(-0.4, 0.4, n_y - 1)) * np.diff(y)
        mu = mu_from_y(y_check, rc * rc)
        res = albedo(lobe_at(key, rc * rc), mu, tol=tol)
        evaluations += res.evaluations
        node_error = max(node_error, float(np.max(res.E_error)))
        measured = max(measured, float(np.max(np.abs(table.E(mu, rc * rc) - res.E))))
    return replace(table, measured=measured, node_error=node_error,
                   error=TABLE_ERROR_SAFETY * measured + node_error,
                   build_seconds=time.perf_counter() - t0, build_evaluations=evaluations)


#: How long a build inside a request waits for its model's compiled loops (queued first
#: for the background thread; loading them from numba's cache takes ~0.5 s, compiling
#: ~5 s): the numpy build is ~10× slower, so waiting a moment pays. Outside a request
#: (the CLI, the background table builds) the build waits for the compile.
KERNEL_WAIT_S = 2.5


def compiled(lobe: BRDF) -> bool:
    """Whether a build of this lobe runs on its compiled loops (in a request, after waiting
    a moment for them; elsewhere after compiling them)."""
    b = budget.current()
    if b is None:
        return kernels.compile_now(lobe, "albedo") is not None
    return kernels.wait(lobe, min(KERNEL_WAIT_S, 0.5 * (b.seconds - b.elapsed())), "albedo") is not None


def predict_build_seconds(key: tuple, alpha: float, base_ready: bool) -> float:
    """Seconds the default-size build of ``key`` should take: one row of its nodes (E at
    its n μ, at ``alpha``) timed and scaled to the build's rows (the check rows included; a
    Schlick basis' split cells: ×1.3, and its base table unless ``base_ready``). A row, not
    a few points scaled: a call's fixed cost (~5 ms) times 900 predicted 8 s for a 0.6 s
    GGX build. Shape-invariant NDFs: the second of two rows (the first builds what the
    whole build shares, e.g. exponential power's Λ table); the others build their Smith Λ
    table at every row, as the first row does."""
    lobe = lobe_at(key, alpha)
    n = TABLE_N_Y if compiled(lobe) else SLOW_TABLE_N
    mu = mu_from_y(np.linspace(0.0, 1.0, n) ** Y_GRADING, alpha)
    seconds = []
    for _ in range(2 if lobe.ndf.shape_invariant else 1):
        t0 = time.perf_counter()
        albedo(lobe, mu, tol=BUILD_TOL)
        seconds.append(time.perf_counter() - t0)
    scale = 1.0 if key[-1] is None else 1.3 + (0 if base_ready else 1)
    return scale * seconds[-1] * build_points(n, n) / n


def build_for_key(key: tuple, base: ETable | None = None) -> ETable:
    """The default-size table for ``key`` (``base``: the F = 1 table of the same lobe, for
    a Schlick basis). A lobe without the compiled integrand whose SLOW_TABLE_N² table the
    budget refuses gets the COARSE_TABLE_N² one if that fits (TableTooSlow otherwise)."""
    if compiled(lobe_at(key, 0.25)):
        return build(key, TABLE_N_Y, TABLE_N_R, base=base)
    try:
        return build(key, SLOW_TABLE_N, SLOW_TABLE_N, base=base)
    except TableTooSlow:
        if base is not None:      # the Schlick basis takes its base's grid: no coarser one
            raise
        return build(key, COARSE_TABLE_N, COARSE_TABLE_N, base=base)
