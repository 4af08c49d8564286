"""The albedo E(μ) of a model over a scene's range of roughness and angles, on the nodes
the advice measures its errors at, and the bound on the largest error between two models
over the range (docs/advise.md §2, §3)."""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..integrate import budget
from ..integrate.albedo import DEFAULT_TOL
from ..integrate.cache import Keyed, complete_only, freeze
from ..integrate.methods import albedo_by
from ..integrate.tables import mu_from_y, y_from_mu
from ..model import make_spec

#: α nodes of the range (geometric) and μ nodes per α (uniform in Smith's y).
N_ALPHA = 6
N_MU = 9
#: Tolerance of each quadrature E (the /albedo default); its error bound enters max_error.
QUAD_TOL = DEFAULT_TOL
#: max_error = GRID_SAFETY × (node error); the largest |ΔE| grows between nodes. Measured
#: (as in tests/analysis/test_advise.py: this 6 × 9 grid against 24 α × (36 nodes in y joined with
#: 36 uniform in θ), tol 1e-6; α ranges [1e-4, 1], [0.01, 1], [0.05, 0.5], [0.2, 0.3],
#: [0.1, 0.5], [0.02, 0.2] with θ_max 90°, 80°, 60°, 70°, 85°; GGX, Beckmann, dielectric,
#: conductor, direction-correlated and Kulla-Conty models; every single alternative, 67
#: cases): the largest growth was 1.48× (Walter's Λ on Beckmann, α ∈ [0.02, 0.2],
#: θ ≤ 85°, whose small error oscillates in a), then 1.13× (Schlick for gold), the rest
#: ≤ 1.04×. 2 covers it with margin.
GRID_SAFETY = 2.0
#: E grids kept (one per model and scene: 54 E and errors, ~1 kB).
GRID_CACHE_ENTRIES = 512


@dataclass(frozen=True)
class Scene:
    alpha_min: float
    alpha_max: float
    theta_max_deg: float

    def alphas(self) -> np.ndarray:
        return np.unique(np.geomspace(self.alpha_min, self.alpha_max, N_ALPHA))

    def mu(self, alpha: float, n: int = N_MU) -> np.ndarray:
        """n cosines uniform in y from θ_max to the normal (fewer if they coincide)."""
        y0 = float(y_from_mu(np.cos(np.radians(self.theta_max_deg)), alpha))
        return np.unique(np.clip(mu_from_y(np.linspace(y0, 1.0, n), alpha), 0.0, 1.0))


def is_anisotropic(values: dict) -> bool:
    return values.get("alpha_y") is not None and values["alpha_y"] != values["alpha"]


@dataclass
class Grid:
    """E and its quadrature error bound at the scene's nodes, one array per α."""
    E: list
    E_error: list
    evaluations: int
    seconds: float
    complete: bool


def albedo_grid(model: dict, scene: Scene, method: str = "quadrature", name: str = "",
                cache: bool = True, **kw) -> Grid:
    """E at every α of the range, or at the first ones only, when the time budget would
    not cover another row at the rate so far (``complete`` False: no bound over the range).

    With ``cache``, from a bounded cache of grids that were computed whole with no cut
    (keyed by the model's values, not by how the request spelled them): a request cut by
    the budget keeps the grids it finished, and the next one, or the same scene at
    another tol, starts from them. ``seconds`` is then that of the first computation."""
    if not cache:
        return _compute_grid(model, scene, method, name, kw)
    key = make_spec(**model).at_alpha(1.0).key()
    return _grid_cached(Keyed((model, name), key), scene, method, tuple(sorted(kw.items())))


@complete_only(GRID_CACHE_ENTRIES, complete=lambda grid: grid.complete)
def _grid_cached(model: Keyed, scene: Scene, method: str, kw: tuple) -> Grid:
    """``model.value``: (the model dict, what a note calls it); keyed by its values."""
    values, name = model.value
    return _compute_grid(values, scene, method, name, dict(kw))


def _compute_grid(model: dict, scene: Scene, method: str, name: str, kw: dict) -> Grid:
    E, err, evals, t0 = [], [], 0, time.perf_counter()
    alphas = scene.alphas()
    base = make_spec(**model)
    for alpha in alphas:
        if E and not _affords((time.perf_counter() - t0) / len(E)):
            _cut(f"advise: E of {name or method} stopped at α = {alpha:.3g} (no time left)")
            break
        res = albedo_by(base.at_alpha(alpha).brdf(), scene.mu(alpha),
                        method=method, tol=QUAD_TOL, average=False, **kw)
        E.append(np.asarray(res["E"], dtype=float))
        err.append(np.asarray(res["E_error"], dtype=float))
        evals += int(res["evaluations"])
    freeze(E + err)
    return Grid(E, err, evals, time.perf_counter() - t0, len(E) == len(alphas))


def model_error(ref: Grid, alt: Grid, scene: Scene) -> dict | None:
    """The bound on max |E_alt − E_ref| over the range (module docstring) and where the
    largest node difference is; None if either grid does not cover the range."""
    if not (ref.complete and alt.complete):
        return None
    worst, where, quad = -1.0, (0.0, 0.0), 0.0
    for alpha, a, r, ea, er in zip(scene.alphas(), alt.E, ref.E, alt.E_error, ref.E_error):
        d = np.abs(a - r)
        i = int(np.argmax(d))
        if d[i] > worst:
            worst, where = float(d[i]), (float(alpha), float(np.degrees(np.arccos(scene.mu(alpha)[i]))))
        quad = max(quad, float(np.max(ea + er)))
    # an albedo difference cannot exceed 1 (both E lie in [0, 1]): the bound says no more
    return {"max_error": min(1.0, GRID_SAFETY * (worst + quad) + quad), "node_max": worst,
            "quadrature_error": quad, "worst_alpha": where[0], "worst_theta_deg": where[1]}


def _affords(seconds: float) -> bool:
    b = budget.current()
    return b is None or b.affords(seconds)


def _cut(note: str) -> None:
    b = budget.current()
    if b is not None:
        b.cut(note)
