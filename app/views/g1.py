"""Smith's Λ and G1 over the view angle."""
from __future__ import annotations

from .. import quantities
from ..figures.curves import g1_figure
from . import schemas
from .view import View, curve_limits

VIEW = View(
    "g1", "Masking Λ and G1",
    "Λ(θ_v) and G1(θ_v) = 1/(1+Λ) for θ_v = 0..90°: the share of facets visible from v.",
    schemas.CurveQuery, schemas.CurveQuery,
    lambda spec, q: quantities.g1_curve(spec.brdf(), q.phi_deg, q.n),
    lambda data, spec, q: g1_figure(data, spec.values),
    curve_limits,
    overlayable=True)
