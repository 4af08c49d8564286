"""Smith masking: Λ → G1 → G2, all from μΛ (finite everywhere).

With a = μ(1 + Λ) = μ + μΛ (> 0 for any α > 0):

* G1(ω) = μ / a                                            (3-5), (3-8)

The joint masking-shadowing forms built on it are in ``g2.py``.

References
----------
Heitz 2014, JCGT 3(2), eq. 43.
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from .numeric import where_valid
from .smith_integral import mu_Lambda_numeric


@dataclass(frozen=True)
class Masking:
    """How μΛ is obtained for a direction. ``applies_to`` None means every NDF."""
    name: str
    label: str
    description: str
    mu_Lambda: Callable  # (ndf, w) -> μΛ(w)
    applies_to: tuple[str, ...] | None = None


def _stretched(ndf, w):
    """(μ, s, sinθ) with s = α(φ) sinθ: the inputs of every approximation below."""
    w = np.asarray(w, dtype=float)
    mu = np.maximum(w[..., 2], 0.0)
    return mu, ndf.stretched_sin(w), np.sqrt(w[..., 0] ** 2 + w[..., 1] ** 2)


def _alpha_phi(s, sin_theta):
    """α(φ) = s / sinθ; at the pole (sinθ = 0) any value will do, every caller
    multiplies it by 1 − μ = 0 there."""
    return where_valid(sin_theta > 0, [s, sin_theta], lambda a, b: a / b, 0.0)


def walter_mu_Lambda(ndf, w):
    """Walter 2007 eq. 27 (seed (3-31), constants corrected in MATH.md):
    Λ(a) ≈ (1 − 1.259a + 0.396a²)/(3.535a + 2.181a²) for a < 1.6, else 0.
    Times μ = a·s: μΛ ≈ s (1 − 1.259a + 0.396a²)/(3.535 + 2.181a)."""
    mu, s, _ = _stretched(ndf, w)

    def formula(m, ss):
        a = m / ss
        return np.where(a < WALTER_A_MAX, ss * (1.0 - 1.259 * a + 0.396 * a * a) / (3.535 + 2.181 * a), 0.0)
    return where_valid(s > 0, [mu, s], formula, 0.0)


# Walter's fit is set to Λ = 0 from a = 1.6 on (where the exact Λ < 3.4e-3).
WALTER_A_MAX = 1.6


def schlick_mu_Lambda(k_of_alpha):
    """Schlick-GGX G1 = μ/(μ(1 − k) + k) (seed 004) is Λ = k(1 − μ)/μ: μΛ = k(1 − μ).
    k from α(φ) of the direction, so the approximation follows anisotropy."""
    def mu_Lambda(ndf, w):
        mu, s, sin_t = _stretched(ndf, w)
        return k_of_alpha(_alpha_phi(s, sin_t)) * (1.0 - mu)
    return mu_Lambda


MASKINGS: dict[str, Masking] = {
    m.name: m for m in [
        Masking("smith", "Smith (exact Λ)",
                "The NDF's own Smith Λ: closed form for GGX, Beckmann, Student-t; a table of "
                "the Smith integral for GTR and exponential power; Walter's Beckmann "
                "substitution for Blinn-Phong (Heitz 2014, eq. 43).",
                lambda ndf, w: ndf.mu_Lambda(w)),
        Masking("smith_numeric", "Smith integral (numerical reference)",
                "G1 = μ / ∫ D(m)(ω·m)⁺ dm by Gauss quadrature (3-6): the reference every "
                "closed form and approximation is checked against.",
                lambda ndf, w: mu_Lambda_numeric(ndf, w)),
        Masking("walter", "Walter rational fit",
                "Walter 2007's rational approximation of Beckmann's Λ (3-31), cheap, "
                "no erf.", walter_mu_Lambda, applies_to=("beckmann", "blinn_phong")),
        Masking("karis", "Karis (3-39)",
                "G1 ≈ 2μ/(μ(2 − α) + α) (Karis 2013); identical to Schlick-GGX with "
                "k = α/2.", schlick_mu_Lambda(lambda a: 0.5 * a), applies_to=("ggx",)),
        Masking("schlick_direct", "Schlick-GGX, direct light",
                "G1 = μ/(μ(1−k)+k), k = (r+1)²/8 with r = √α (Karis 2013, as in "
                "LearnOpenGL).", schlick_mu_Lambda(lambda a: (np.sqrt(a) + 1.0) ** 2 / 8.0),
                applies_to=("ggx",)),
        Masking("schlick_ibl", "Schlick-GGX, image-based light",
                "G1 = μ/(μ(1−k)+k), k = r²/2 = α/2 (Karis 2013).",
                schlick_mu_Lambda(lambda a: 0.5 * a), applies_to=("ggx",)),
    ]
}


def G1(mu, mu_Lambda):
    """G1 = 1/(1+Λ) = μ/(μ + μΛ); 0 at μ ≤ 0 (χ⁺ of (3-8))."""
    mu = np.asarray(mu, dtype=float)
    return where_valid(mu > 0, [mu, mu_Lambda], lambda m, ml: m / (m + ml), 0.0)
