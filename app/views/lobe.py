"""f in the plane of incidence."""
from __future__ import annotations

from .. import quantities
from ..figures.lobes import lobe_figure
from . import schemas
from .view import View, curve_limits

VIEW = View(
    "lobe", "BRDF lobe",
    "f in the plane of incidence, θ_o = −90..90° (positive on the mirror side).",
    schemas.LobeQuery, schemas.LobeFigureQuery,
    lambda spec, q: quantities.lobe_curve(spec.brdf(), q.theta_i_deg, q.phi_i_deg, q.n, q.cosine),
    lambda data, spec, q: lobe_figure(data, spec.values, q.theta_i_deg, q.log),
    curve_limits,
    overlayable=True)
