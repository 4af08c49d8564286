"""An independent quadrature of the split-sum integrals of Schlick-GGX, written for the
tests (nothing from app/): Karis 2013's estimator G·(v·h)/(μ_v μ_h), averaged over
microfacet normals h distributed as D(h)(n·h) — here by a dense Gauss-Legendre product
rule instead of random samples.

With ξ = tan²θ_h/(α² + tan²θ_h) (the GGX CDF of θ_h under D(h)(n·h), Walter et al.
2007, eq. 35 inverted) and the azimuth φ of h uniform, the weight D(h)(n·h)dω_h is
dξ dφ/(2π), so E = mean over (ξ, φ) of G·(v·h)/(μ_v μ_h) · [μ_l > 0] with
l = 2(v·h)h − v. E₁ with F = 1; E_S with F = (1 − v·h)⁵ (Schlick 1994).

G1 = μ/(μ(1 − k) + k), k = α/2 (Schlick-GGX for image-based light, Karis 2013), i.e.
Λ = k(1 − μ)/μ; separable G2 = G1(l)G1(v); height-correlated G2 = 1/(1 + Λ_l + Λ_v)
(Heitz 2014, eq. 99). The indicator [μ_l > 0] is not integrated across: the θ_h-range is
split where the horizon starts to cut the azimuths, and there φ runs over the part kept
(closed form of μ_l = 0). With N_XI × N_PHI = 384 × 64 nodes, E₁ and E_S differ from a
768 × 256 rule by ≤ 3e-6 (α = 0.004, 0.05, 0.3; μ from 1e-3 to 1, height-correlated):
far below the differences between the conventions a check must tell apart. The error is
ξ's: 192 azimuths instead of 64 changed nothing at 384 ξ-nodes, and cost three times as
much (the lut tests' largest cost).
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np

N_XI, N_PHI = 384, 64


@lru_cache(maxsize=None)
def _legendre(n: int):
    """Gauss-Legendre nodes and weights on [−1, 1] (an eigenproblem: made once per n)."""
    return np.polynomial.legendre.leggauss(n)


def _nodes(n: int, a: float, b: float):
    x, w = _legendre(n)
    return 0.5 * (b - a) * x + 0.5 * (b + a), 0.5 * (b - a) * w


def k_ibl(alpha: float) -> float:
    """Schlick-GGX's k for image-based light, α/2 (Karis 2013)."""
    return alpha / 2.0


def k_direct(alpha: float) -> float:
    """Schlick-GGX's k for direct light, (r + 1)²/8 with r = √α (Karis 2013)."""
    return (np.sqrt(alpha) + 1.0) ** 2 / 8.0


def split_sum_integrals(alpha: float, mu_v: np.ndarray, g2: str, n_xi: int = N_XI, n_phi: int = N_PHI,
                        k_of=k_ibl):
    """(E₁, E_S) at one α for view cosines ``mu_v`` (array, > 0)."""
    k = k_of(alpha)
    g, wg = _legendre(n_phi)
    e1, es = [], []
    for mv in np.atleast_1d(mu_v):
        sv = np.sqrt(1.0 - mv * mv)
        theta_v = np.arccos(mv)
        # the horizon cuts the h-azimuths from θ_h = (π/2 − θ_v)/2 on and leaves none from
        # (π/2 + θ_v)/2 on: one Gauss rule below the first (all φ), one between the two over
        # the φ that keep μ_l > 0 only, in t with ξ = ξ_c + (ξ_m − ξ_c)(1 − cos πt)/2 (the
        # φ-range opens like a square root at both ends; this map makes it smooth)
        xi_c, xi_m = (_xi(np.pi / 4 - theta_v / 2, alpha), _xi(np.pi / 4 + theta_v / 2, alpha))
        x1, w1 = _nodes(n_xi // 2, 0.0, xi_c)
        t, wt = _nodes(n_xi // 2, 0.0, 1.0)
        x2 = xi_c + (xi_m - xi_c) * 0.5 * (1.0 - np.cos(np.pi * t))
        w2 = wt * (xi_m - xi_c) * 0.5 * np.pi * np.sin(np.pi * t)
        xi, w_xi = np.concatenate([x1, x2]), np.concatenate([w1, w2])
        cos2 = (1.0 - xi) / (1.0 + (alpha * alpha - 1.0) * xi)
        mu_h, sin_h = np.sqrt(cos2), np.sqrt(1.0 - cos2)
        cos_max = np.ones_like(xi) * -1.0
        cut = (np.arange(xi.size) >= x1.size) & (sv > 0)      # at normal view the second range is empty
        cos_max[cut] = np.clip(mv * (1.0 - 2.0 * cos2[cut]) / (2.0 * mu_h[cut] * sv * sin_h[cut]), -1.0, 1.0)
        phi_max = np.arccos(cos_max)[:, None]
        phi = 0.5 * phi_max * (g[None, :] + 1.0)
        w = w_xi[:, None] * 0.5 * phi_max * wg[None, :] / np.pi
        mu_h, sin_h = mu_h[:, None], sin_h[:, None]
        vh = sv * sin_h * np.cos(phi) + mv * mu_h
        ml = np.maximum(2.0 * vh * mu_h - mv, 0.0)
        if g2 == "separable":
            G = ml / (ml * (1 - k) + k) * mv / (mv * (1 - k) + k)
        else:
            G = ml * mv / (ml * mv + k * (1 - ml) * mv + k * (1 - mv) * ml)
        g_vis = G * vh / (mv * mu_h)
        fc = np.clip(1.0 - vh, 0.0, 1.0) ** 5
        e1.append(np.sum(w * g_vis))
        es.append(np.sum(w * g_vis * fc))
    return np.array(e1), np.array(es)


def _xi(theta_h: float, alpha: float) -> float:
    """The GGX CDF of θ_h: tan²θ_h/(α² + tan²θ_h)."""
    t2 = np.tan(theta_h) ** 2
    return t2 / (alpha * alpha + t2)
