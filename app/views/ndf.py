"""D(θ_m) along one azimuth."""
from __future__ import annotations

from .. import quantities
from ..figures.curves import ndf_figure
from . import schemas
from .view import View, curve_limits

VIEW = View(
    "ndf", "Normal distribution D",
    "D(θ_m) at azimuth φ, θ_m = 0..90°: how densely the microfacet normals point "
    "each way.",
    schemas.NdfQuery, schemas.NdfFigureQuery,
    lambda spec, q: quantities.ndf_curve(spec.brdf(), q.phi_deg, q.n, q.cosine),
    lambda data, spec, q: ndf_figure(data, spec.values, q.log),
    curve_limits,
    overlayable=True)
