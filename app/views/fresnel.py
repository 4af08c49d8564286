"""The Fresnel factor over the difference angle."""
from __future__ import annotations

from .. import quantities
from ..figures.fresnel import fresnel_figure
from . import schemas
from .view import View, curve_limits

VIEW = View(
    "fresnel", "Fresnel F",
    "F(θ_d) for θ_d = 0..90°; for Schlick also the exact dielectric of the same F₀ and "
    "the error.",
    schemas.FresnelQuery, schemas.FresnelQuery,
    lambda spec, q: quantities.fresnel_curve(spec.brdf(), q.n),
    lambda data, spec, q: fresnel_figure(data, spec.values),
    curve_limits,
    overlayable=True)
