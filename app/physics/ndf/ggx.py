"""GGX / Trowbridge-Reitz (seed 000 (3-34)..(3-36); seed 001).

References
----------
Walter, Marschner, Li, Torrance 2007, "Microfacet Models for Refraction through Rough
Surfaces", EGSR, eq. 33-34. Heitz 2014, JCGT 3(2), eq. 85-86 (anisotropic form).
"""
from __future__ import annotations

import numpy as np

from . import register
from .base import ShapeInvariantNDF
from ..numeric import where_valid


@register
class GGX(ShapeInvariantNDF):
    name = "ggx"
    label = "GGX (Trowbridge-Reitz)"
    description = "Long-tailed NDF of Walter et al. 2007; the real-time default."
    menu_order = 0
    reference = "Walter et al. 2007, eq. 33; Heitz 2014, eq. 85"

    def _D(self, mz, q2):
        # D = 1 / (π α_x α_y cos⁴θ (1 + r²)²) with r² = q²/mz², multiplied through by
        # mz⁴: no division by mz, and at mz = 0 it is the limit 1/(π α_x α_y q⁴).
        return 1.0 / (np.pi * (mz * mz + q2) ** 2)

    def _mu_Lambda(self, mu, s):
        # Λ = (−1 + √(1 + 1/a²))/2, a = μ/s (3-36), times μ: (√(μ²+s²) − μ)/2,
        # written without the cancellation for s ≪ μ.
        return s * s / (2.0 * (np.sqrt(mu * mu + s * s) + mu))

    def radial_cdf(self, r2):
        # ∫ 2π r / (π (1 + r²)²) dr from 0 to r̃ = r̃² / (1 + r̃²); 1 at r̃ = ∞.
        return where_valid(np.isfinite(r2), [r2], lambda r: r / (1.0 + r), 1.0)

    def radial_cdf_inv(self, u):
        return u / (1.0 - u)

    def radial_ccdf(self, r2):
        return 1.0 / (1.0 + r2)

    def radial_ccdf_inv(self, v):
        return (1.0 - v) / v
