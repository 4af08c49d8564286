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


@dataclass(frozen=True)
class Masking:
    """How μΛ is obtained for a direction. ``applies_to`` None means every NDF."""
    name: str
    label: str
    description: str
    mu_Lambda: Callable  # (ndf, w) -> μΛ(w)
    applies_to: tuple[str, ...] | None = None


MASKINGS: dict[str, Masking] = {
    m.name: m for m in [
        Masking("smith", "Smith (exact Λ)",
                "The NDF's own Smith Λ, closed form where one exists (Heitz 2014, eq. 43).",
                lambda ndf, w: ndf.mu_Lambda(w)),
    ]
}


def G1(mu, mu_Lambda):
    """G1 = 1/(1+Λ) = μ/(μ + μΛ); 0 at μ ≤ 0 (χ⁺ of (3-8))."""
    mu = np.asarray(mu, dtype=float)
    return where_valid(mu > 0, [mu, mu_Lambda], lambda m, ml: m / (m + ml), 0.0)
