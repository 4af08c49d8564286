"""f over the hemisphere of v."""
from __future__ import annotations

from .. import quantities
from ..figures.lobes import lobe3d_figure
from . import schemas
from .view import View, grid_limits

VIEW = View(
    "lobe3d", "3-D lobe",
    "f over the hemisphere of v (θ rows × φ columns) for a fixed light direction.",
    schemas.Lobe3dQuery, schemas.Lobe3dFigureQuery,
    lambda spec, q: quantities.lobe_grid(spec.brdf(), q.theta_i_deg, q.phi_i_deg, q.n_theta, q.n_phi),
    lambda data, spec, q: lobe3d_figure(data, spec.values, q.theta_i_deg, q.phi_i_deg, q.log),
    grid_limits,
    heavy=True, layout="wide")
