"""The masking-shadowing G2 over both angles."""
from __future__ import annotations

from .. import quantities
from ..figures.maps import g2_figure
from . import schemas
from .view import View, square_grid_limits

VIEW = View(
    "g2", "Masking-shadowing G2",
    "G2(θ_l, θ_v) over θ_l, θ_v = 0..90° (rows θ_l) with v at azimuth φ from l.",
    schemas.G2Query, schemas.G2Query,
    lambda spec, q: quantities.g2_grid(spec.brdf(), q.phi_deg, q.n),
    lambda data, spec, q: g2_figure(data, spec.values, q.phi_deg),
    square_grid_limits)
