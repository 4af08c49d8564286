"""f over the half and difference angles (the Disney explorer's image slice)."""
from __future__ import annotations

from .. import quantities
from ..figures.images import slice_figure
from . import schemas
from .view import View, square_grid_limits

VIEW = View(
    "slice", "Half/difference slice",
    "f over θ_h × θ_d at fixed φ_h, φ_d (the Disney explorer's image slice; rows θ_d, "
    "null below the horizon).",
    schemas.SliceQuery, schemas.SliceFigureQuery,
    lambda spec, q: quantities.half_difference_slice(spec.brdf(), q.phi_h_deg, q.phi_d_deg,
                                                     q.n, q.cosine),
    lambda data, spec, q: slice_figure(data, spec.values, q.phi_d_deg, q.log),
    square_grid_limits,
    heavy=True)
