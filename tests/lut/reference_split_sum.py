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
(Heitz 2014, eq. 99). The indicator [μ_l > 0] makes the rule converge slowly (~N⁻²):
with N_XI × N_PHI = 384 × 192 nodes, doubling both moves E by ≤ 1e-4 (at μ = 0.02,
α = 0.05), ≤ 2e-6 for μ ≥ 0.1: far below the differences between the conventions a
check must tell apart.
"""
from __future__ import annotations

import numpy as np

N_XI, N_PHI = 384, 192


def _nodes(n: int, a: float, b: float):
    x, w = np.polynomial.legendre.leggauss(n)
    return 0.5 * (b - a) * x + 0.5 * (b + a), 0.5 * (b - a) * w


def split_sum_integrals(alpha: float, mu_v: np.ndarray, g2: str, n_xi: int = N_XI, n_phi: int = N_PHI):
    """(E₁, E_S) at one α for view cosines ``mu_v`` (array, > 0)."""
    k = alpha / 2.0
    xi, w_xi = _nodes(n_xi, 0.0, 1.0)
    phi, w_phi = _nodes(n_phi, 0.0, np.pi)          # symmetric in φ: [0, π] is the mean over [0, 2π]
    cos2 = (1.0 - xi) / (1.0 + (alpha * alpha - 1.0) * xi)
    mu_h = np.sqrt(cos2)[:, None]
    sin_h = np.sqrt(1.0 - cos2)[:, None]
    w = (w_xi[:, None] * w_phi[None, :]) / np.pi
    e1, es = [], []
    for mv in np.atleast_1d(mu_v):
        sv = np.sqrt(1.0 - mv * mv)
        vh = sv * sin_h * np.cos(phi)[None, :] + mv * mu_h
        mu_l = 2.0 * vh * mu_h - mv
        ok = (mu_l > 0) & (vh > 0)
        ml = np.where(ok, mu_l, 1.0)
        if g2 == "separable":
            G = ml / (ml * (1 - k) + k) * mv / (mv * (1 - k) + k)
        else:
            G = 1.0 / (1.0 + k * (1 - ml) / ml + k * (1 - mv) / mv)
        g_vis = np.where(ok, G * vh / (mv * mu_h), 0.0)
        fc = np.clip(1.0 - vh, 0.0, 1.0) ** 5
        e1.append(np.sum(w * g_vis))
        es.append(np.sum(w * g_vis * fc))
    return np.array(e1), np.array(es)
