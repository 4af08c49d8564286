"""GGX / Trowbridge-Reitz.

References
----------
Walter, Marschner, Li, Torrance 2007, "Microfacet Models for Refraction through Rough
Surfaces", EGSR, eq. 33-34. Heitz 2014, JCGT 3(2), eq. 85-86 (anisotropic form).
Heitz 2018, "Sampling the GGX Distribution of Visible Normals", JCGT 7(4), listing 1.
"""
from __future__ import annotations

import math

import numpy as np

from ..formula import Formula
from ..numeric import where_valid
from ..scalar import scalar
from ..vectors import unit
from .base import NDFS, ShapeInvariantNDF


@NDFS.register
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
        # Λ = (−1 + √(1 + 1/a²))/2, a = μ/s (Walter et al. 2007, eq. 34), times μ:
        # (√(μ²+s²) − μ)/2, written without the cancellation for s ≪ μ.
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

    # The one spelling of D and μΛ for the compiled kernels and the shaders (_D and
    # _mu_Lambda above are the numpy reference they are tested against).
    D_formula = Formula(
        "D_ggx", ("mz", "q2"), "1.0 / (PI * t * t)", body=(("t", "mz * mz + q2"),),
        consts=(("PI", math.pi, "π"),),
        doc="GGX: α_x α_y D = 1/(π (mz² + q²)²) (Walter et al. 2007, eq. 33; Heitz 2014, eq. 85).")
    mu_Lambda_formula = Formula(
        "muLambda_ggx", ("mu", "s2"), "s2 / (2.0 * (sqrt(mu * mu + s2) + mu))",
        doc="GGX's Smith μΛ = (√(μ² + s²) − μ)/2, without the cancellation (Heitz 2014, eq. 86);\n"
            "it reads s² alone (no square root of it taken and squared again).")

    @staticmethod
    @scalar
    def radial_ccdf_scalar(r2, p):
        return 1.0 / (1.0 + r2)

    @staticmethod
    @scalar
    def radial_cdf_inv_scalar(u, p):
        return u / (1.0 - u)

    @staticmethod
    @scalar
    def radial_ccdf_inv_scalar(v, p):
        return (1.0 - v) / v

    def sample_visible(self, v, u):
        """Heitz 2018, listing 1: stretch v; a uniform point on the disk, warped onto the
        projection of the visible hemisphere (half disk squeezed by s = (1 + V_z)/2);
        lift to the hemisphere about V; unstretch. v (k, 3), u (n, ≥2) → m (k, n, 3)."""
        V = unit(np.stack([self.alpha_x * v[..., 0], self.alpha_y * v[..., 1], v[..., 2]],
                          axis=-1))[..., None, :]
        len2 = V[..., 0] ** 2 + V[..., 1] ** 2
        # Orthonormal basis (T1, T2, V); T1 = (1, 0, 0) at normal incidence.
        inv_len = where_valid(len2 > 0, [len2], lambda x: 1.0 / np.sqrt(x), 0.0)
        T1 = np.where((len2 > 0)[..., None],
                      np.stack([-V[..., 1] * inv_len, V[..., 0] * inv_len, np.zeros_like(len2)], axis=-1),
                      np.array([1.0, 0.0, 0.0]))
        T2 = np.cross(V, T1)
        r = np.sqrt(u[..., 0])
        phi = 2.0 * np.pi * u[..., 1]
        t1 = r * np.cos(phi)
        t2 = r * np.sin(phi)
        s = 0.5 * (1.0 + V[..., 2])
        t2 = (1.0 - s) * np.sqrt(np.maximum(0.0, 1.0 - t1 * t1)) + s * t2
        tz = np.sqrt(np.maximum(0.0, 1.0 - t1 * t1 - t2 * t2))
        Nh = t1[..., None] * T1 + t2[..., None] * T2 + tz[..., None] * V
        return unit(np.stack([self.alpha_x * Nh[..., 0], self.alpha_y * Nh[..., 1],
                              np.maximum(0.0, Nh[..., 2])], axis=-1))
