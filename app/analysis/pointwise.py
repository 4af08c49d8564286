"""The pointwise metric of the advice: what a point light shows is f itself, so a cheaper
model is rated by the largest relative error of f over the scene's range of α and of both
angles (docs/advise.md §2b), not by its albedo.

error = |f_alt − f_ref| / max(f_ref, F_FLOOR), the largest over α nodes (those of the
albedo metric), θ_l, θ_v ∈ [0, θ_max] and the azimuth difference φ ∈ [0°, 180°]
(isotropic models only, as the advice). F_FLOOR keeps f near zero (grazing, far from the
lobe) from turning a negligible absolute difference into a large relative one.
"""
from __future__ import annotations

import time
from dataclasses import dataclass

import numpy as np

from ..model import make_spec
from ..physics.numeric import where_valid
from ..physics.vectors import direction_deg
from .albedo_grid import Scene, _affords, _cut

#: f below which the error is taken relative to this floor instead of f (1/sr): 1 % of a
#: white Lambertian surface's f = 1/π, the least a viewer sees against diffuse light.
F_FLOOR = 0.01 / np.pi
#: Nodes per polar angle (uniform in θ from 0 to θ_max) and of the azimuth difference.
N_THETA = 16
N_PHI = 9
#: max_error = POINTWISE_SAFETY × the largest node error: the error grows between nodes.
#: Measured against a grid 4× finer in every angle and 21 α nodes (bench/advise_pointwise.py,
#: 4 scenes, 19 alternatives): the largest growth was 1.014× (Karis's Λ, α ∈ [0.01, 0.3],
#: θ ≤ 70°); the errors peak at the range's corners, which are nodes. 1.5 covers it.
POINTWISE_SAFETY = 1.5


@dataclass
class PointGrid:
    """f at the scene's nodes, one (θ_l, θ_v, φ) array per α."""
    f: list
    evaluations: int
    seconds: float
    complete: bool


def directions(scene: Scene, n_theta: int = N_THETA, n_phi: int = N_PHI):
    """l at azimuth 0 and v at azimuth φ, broadcast over (θ_l, θ_v, φ)."""
    theta = np.linspace(0.0, scene.theta_max_deg, n_theta)
    phi = np.linspace(0.0, 180.0, n_phi)
    l = direction_deg(theta[:, None, None], 0.0)
    v = direction_deg(theta[None, :, None], phi[None, None, :])
    return np.broadcast_arrays(l, v)


def f_grid(model: dict, scene: Scene, alphas=None, n_theta: int = N_THETA,
           n_phi: int = N_PHI, name: str = "") -> PointGrid:
    """f of ``model`` at every α of the range (or ``alphas``) on the angle nodes; stops
    early, incomplete, when the time budget would not cover another α."""
    l, v = directions(scene, n_theta, n_phi)
    out, t0 = [], time.perf_counter()
    alphas = scene.alphas() if alphas is None else alphas
    base = make_spec(**model)
    for alpha in alphas:
        if out and not _affords((time.perf_counter() - t0) / len(out)):
            _cut(f"advise: f of {name or 'a model'} stopped at α = {alpha:.3g} (no time left)")
            break
        out.append(base.at_alpha(alpha).brdf().evaluate(l, v, ("f",))["f"])
    return PointGrid(out, len(out) * l[..., 0].size, time.perf_counter() - t0,
                     len(out) == len(alphas))


def relative_error(f_ref, f_alt) -> np.ndarray:
    """|f_alt − f_ref| / max(f_ref, F_FLOOR) where f_ref is finite; 0 where it diverges
    (both directions at 90°, where a relative error has no meaning and a light adds
    nothing). An alternative that diverges where the reference does not is infinitely off."""
    return where_valid(np.isfinite(f_ref), [f_ref, f_alt],
                       lambda r, a: np.abs(a - r) / np.maximum(r, F_FLOOR), 0.0)


def pointwise_error(ref: PointGrid, alt: PointGrid, scene: Scene) -> dict | None:
    """The bound POINTWISE_SAFETY × the largest node error, that node error and where it
    is; None if either grid does not cover the range."""
    if not (ref.complete and alt.complete):
        return None
    worst, where = -1.0, (0.0, 0.0, 0.0, 0.0)
    theta = np.linspace(0.0, scene.theta_max_deg, N_THETA)
    phi = np.linspace(0.0, 180.0, N_PHI)
    for alpha, r, a in zip(scene.alphas(), ref.f, alt.f):
        err = relative_error(r, a)
        k = np.unravel_index(int(np.argmax(err)), err.shape)
        if err[k] > worst:
            worst = float(err[k])
            where = (float(alpha), float(theta[k[0]]), float(theta[k[1]]), float(phi[k[2]]))
    return {"max_error": POINTWISE_SAFETY * worst, "node_max": worst, "quadrature_error": 0.0,
            "worst_alpha": where[0], "worst_theta_deg": max(where[1], where[2]),
            "worst_at": {"alpha": where[0], "theta_l_deg": where[1], "theta_v_deg": where[2],
                         "phi_deg": where[3]}}
