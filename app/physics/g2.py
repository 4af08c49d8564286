"""Joint masking-shadowing G2 from G1 and μΛ (masking.py).

With a = μ(1 + Λ) = μ + μΛ:

* separable          G2 = G1(l) G1(v)                      (3-10)
* height-correlated  G2 = 1 / (1 + Λ(l) + Λ(v))            (3-17)

Each form returns G2 and the visibility V = G2 / (4 μ_l μ_v), written so that it stays
finite when one direction grazes (it tends to a constant there); it diverges only where
both directions graze under the height-correlated form, and is +inf there.

A form's ``G2_and_V(mu_l, mu_v, ml_l, ml_v, *, phi, ndf, lambda_phi)`` receives μ ≥ 0,
μΛ, and — only if it declares ``needs_phi`` — the azimuth difference φ ∈ [0, π] of l
and v, the NDF and the chosen λ(φ).

References
----------
Heitz 2014, JCGT 3(2), eq. 98 (separable), 99 (height-correlated).
"""
from __future__ import annotations

from dataclasses import dataclass
from typing import Callable

import numpy as np

from .numeric import where_valid


def _ratio(num, den):
    """num/den where den > 0; where den = 0 the caller's quantity is 0 (for G2) ."""
    return where_valid(den > 0, [num, den], lambda n, d: n / d, 0.0)


def _visibility(den4):
    """V = 1/den4 where den4 > 0, +inf where it is 0 (a true divergence)."""
    return where_valid(den4 > 0, [den4], lambda d: 1.0 / d, np.inf)


def separable(mu_l, mu_v, ml_l, ml_v, **_):
    """G2 = G1(l) G1(v) (3-10), V = 1 / (4 (μ_l + μ_lΛ_l)(μ_v + μ_vΛ_v))."""
    a_l, a_v = mu_l + ml_l, mu_v + ml_v
    return _ratio(mu_l * mu_v, a_l * a_v), _visibility(4.0 * a_l * a_v)


def height_correlated(mu_l, mu_v, ml_l, ml_v, **_):
    """G2 = 1/(1 + Λ_l + Λ_v) (3-17), times μ_l μ_v over itself:
    G2 = μ_l μ_v / (μ_l μ_v + μ_v·μ_lΛ_l + μ_l·μ_vΛ_v)."""
    den = mu_l * mu_v + mu_v * ml_l + mu_l * ml_v
    return _ratio(mu_l * mu_v, den), _visibility(4.0 * den)


@dataclass(frozen=True)
class G2Form:
    name: str
    label: str
    description: str
    G2_and_V: Callable  # (mu_l, mu_v, ml_l, ml_v, *, phi, ndf, lambda_phi) -> (G2, V)
    needs_phi: bool = False
    applies_to: tuple[str, ...] | None = None  # NDF names; None = every NDF


G2_FORMS: dict[str, G2Form] = {
    g.name: g for g in [
        G2Form("separable", "Separable",
               "G1(l)·G1(v): ignores the correlation of masking and shadowing (3-10).",
               separable),
        G2Form("height_correlated", "Height-correlated",
               "1/(1+Λ(l)+Λ(v)): the recommended form (Heitz 2014, eq. 99; (3-17)).",
               height_correlated),
    ]
}


def azimuth_difference(l, v) -> np.ndarray:
    """φ ∈ [0, π] between the projections of l and v on the tangent plane (0 where
    either is along n, where it is undefined and the direction-correlated forms reduce
    to min(G1) — the right limit, since G1 = 1 there)."""
    cross = l[..., 0] * v[..., 1] - l[..., 1] * v[..., 0]
    dot = l[..., 0] * v[..., 0] + l[..., 1] * v[..., 1]
    return np.arctan2(np.abs(cross), dot)
