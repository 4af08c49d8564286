"""Smith masking: how μΛ is obtained for a direction, and G1 = μ/(μ + μΛ).

With a = μ(1 + Λ) = μ + μΛ (> 0 for any α > 0), G1(ω) = μ/a (Heitz 2014, eq. 43); the
joint masking-shadowing forms built on it are in ``g2.py``. Every masking also writes
μΛ for one point (``scalar_mu_Lambda``, physics/scalar.py), given (μ, s = α(φ) sinθ,
sinθ), its own parameters and the NDF's scalar formulas.

References
----------
Heitz 2014, JCGT 3(2), eq. 43; Walter et al. 2007, eq. 27; Karis 2013, "Real Shading in
Unreal Engine 4", SIGGRAPH course notes; Schlick 1994.
"""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .formula import Formula, scalar_function
from .numeric import where_valid
from .registry import Registry
from .scalar import scalar
from .lambda_table import table_params, tabulated_mu_Lambda_scalar
from .smith_table import mu_Lambda_smith_numeric

#: The masking every other one is checked against: the general Smith integral.
REFERENCE = "smith_numeric"


def _no_params(ndf) -> tuple:
    return ()


@dataclass(frozen=True, eq=False)   # a registry entry: compared and hashed by identity
class Masking:
    """How μΛ is obtained for a direction. ``applies_to`` None means every NDF.

    ``approximates`` names the exact masking this one approximates (None: exact, as far
    as the NDF's own Λ is: see :meth:`exact`). ``simplifies_to``: ((values, name), ...)
    where it is another registered masking. ``scalar_mu_Lambda(μ, s, sinθ, p, ndf_p,
    ndf_mu_Lambda, ndf_radial_ccdf, ndf_radial_ccdf_inv)`` with p = kernel_params(ndf).
    """
    name: str
    label: str
    description: str
    mu_Lambda: Callable  # (ndf, w) -> μΛ(w)
    applies_to: tuple[str, ...] | None = None
    approximates: str | None = None
    uses_ndf_Lambda: bool = False     # the NDF's own Λ (exact iff the NDF's smith_exact)
    simplifies_to: tuple[tuple[dict, str], ...] = ()
    scalar_mu_Lambda: Callable | None = None
    kernel_params: Callable = field(default=_no_params)   # (ndf) -> floats
    #: μΛ(mu, s2, sin_t) (s2 = s²) written once (the source of scalar_mu_Lambda and of the shaders'
    #: μΛ); None for the exact maskings, whose μΛ is the NDF's own or the Smith integral.
    formula: Formula | None = None

    def exact(self, ndf) -> "Masking":
        """The exact masking this one stands for with ``ndf`` (itself when exact)."""
        if self.approximates is not None:
            return MASKINGS[self.approximates].exact(ndf)
        if self.uses_ndf_Lambda and not type(ndf).smith_exact:
            return MASKINGS[REFERENCE]
        return self


def _stretched(ndf, w):
    """(μ, s, sinθ) with s = α(φ) sinθ: the inputs of every approximation below."""
    w = np.asarray(w, dtype=float)
    mu = np.maximum(w[..., 2], 0.0)
    return mu, ndf.stretched_sin(w), np.sqrt(w[..., 0] ** 2 + w[..., 1] ** 2)


def _alpha_phi(s, sin_theta):
    """α(φ) = s / sinθ; at the pole (sinθ = 0) any value will do, every caller
    multiplies it by 1 − μ = 0 there."""
    return where_valid(sin_theta > 0, [s, sin_theta], lambda a, b: a / b, 0.0)


# Walter's fit is set to Λ = 0 from a = 1.6 on (where the exact Λ < 3.4e-3).
WALTER_A_MAX = 1.6


def walter_mu_Lambda(ndf, w):
    """Walter 2007 eq. 27: Λ(a) ≈ (1 − 1.259a + 0.396a²)/(3.535a + 2.181a²) for a < 1.6,
    else 0. Times μ = a·s: μΛ ≈ s (1 − 1.259a + 0.396a²)/(3.535 + 2.181a). The numerator
    is negative for 1.5497 < a < 1.6 (Λ down to −5e-5, G1 up to 1.00005): it is bounded
    at 0 there, the value the fit takes from a = 1.6 on."""
    mu, s, _ = _stretched(ndf, w)

    def formula(m, ss):
        a = m / ss
        num = np.maximum(1.0 - 1.259 * a + 0.396 * a * a, 0.0)
        return np.where(a < WALTER_A_MAX, ss * num / (3.535 + 2.181 * a), 0.0)
    return where_valid(s > 0, [mu, s], formula, 0.0)


#: The kernels' scalar masking signature after (μ, s², sinθ): the masking's own p, the
#: NDF's p and its scalar hooks (used by the maskings that defer to the NDF).
_NDF_HOOKS = ("p", "ndf_p", "ndf_mu_Lambda", "ndf_ccdf", "ndf_ccdf_inv")
_ML_ARGS = ("mu", "s2", "sin_t")
_S = ("s", "sqrt(s2)")

WALTER = Formula(
    "muLambda_walter", _ML_ARGS,
    "sel(and_(s > 0.0, a < WALTER_A_MAX), s * max(1.0 - 1.259 * a + 0.396 * a * a, 0.0) / (3.535 + 2.181 * a), 0.0)",
    body=(_S, ("a", "mu / max(s, S_FLOOR)")),
    consts=(("WALTER_A_MAX", WALTER_A_MAX, "Λ = 0 from here on (exact Λ < 3.4e-3 there)"),
            ("S_FLOOR", 1e-30, "keeps a finite on the side not selected (s = 0); float32 has it")),
    doc="Walter 2007's rational fit of Beckmann's Λ (eq. 27), times μ: s (1 − 1.259a + 0.396a²)/(3.535 + 2.181a)\n"
        "for a = μ/s < 1.6, else 0; the numerator, negative just below 1.6, is taken as 0 there.")
walter_mu_Lambda_scalar = scalar_function(WALTER, __name__, "walter_mu_Lambda_scalar", _NDF_HOOKS)


def schlick_mu_Lambda(k_of_alpha):
    """Schlick-GGX G1 = μ/(μ(1 − k) + k) is Λ = k(1 − μ)/μ: μΛ = k(1 − μ).
    k from α(φ) of the direction, so the approximation follows anisotropy."""
    def mu_Lambda(ndf, w):
        mu, s, sin_t = _stretched(ndf, w)
        return k_of_alpha(_alpha_phi(s, sin_t)) * (1.0 - mu)
    return mu_Lambda


_ALPHA_PHI = ("alpha_phi", "sel(sin_t > 0.0, s / sin_t, 0.0)")   # at the pole: × (1 − μ) = 0
HALF_ALPHA = Formula(
    "muLambda_half_alpha", _ML_ARGS, "0.5 * alpha_phi * (1.0 - mu)", body=(_S, _ALPHA_PHI),
    doc="Schlick-GGX G1 = μ/(μ(1 − k) + k) is μΛ = k(1 − μ), k = α(φ)/2 = s/(2 sinθ) (Karis 2013; image-based light).")
SCHLICK_DIRECT = Formula(
    "muLambda_schlick_direct", _ML_ARGS, "(r + 1.0) * (r + 1.0) / 8.0 * (1.0 - mu)",
    body=(_S, _ALPHA_PHI, ("r", "sqrt(alpha_phi)")),
    doc="Schlick-GGX G1 = μ/(μ(1 − k) + k) is μΛ = k(1 − μ), k = (√α(φ) + 1)²/8 (Karis 2013; direct light).")
half_alpha_mu_Lambda_scalar = scalar_function(HALF_ALPHA, __name__, "half_alpha_mu_Lambda_scalar", _NDF_HOOKS)
schlick_direct_mu_Lambda_scalar = scalar_function(SCHLICK_DIRECT, __name__, "schlick_direct_mu_Lambda_scalar",
                                                  _NDF_HOOKS)


@scalar
def smith_mu_Lambda_scalar(mu, s2, sin_t, p, ndf_p, ndf_mu_Lambda, ndf_ccdf, ndf_ccdf_inv):
    return ndf_mu_Lambda(mu, s2, ndf_p)


@scalar
def tabulated_mu_Lambda_masking_scalar(mu, s2, sin_t, p, ndf_p, ndf_mu_Lambda, ndf_ccdf, ndf_ccdf_inv):
    """The general Smith integral through its table (lambda_table.py), p = the table."""
    return tabulated_mu_Lambda_scalar(mu, math.sqrt(s2), p, 0)


#: Every masking by name (``MASKINGS.register(Masking(...))``).
MASKINGS: Registry[Masking] = Registry("masking")
for _m in [
    Masking("smith", "Smith (exact Λ)",
            "The NDF's own Smith Λ: closed form for GGX, Beckmann, Student-t; a table of "
            "the Smith integral for GTR and exponential power; Walter's Beckmann "
            "substitution for Blinn-Phong (Heitz 2014, eq. 43).",
            lambda ndf, w: ndf.mu_Lambda(w), uses_ndf_Lambda=True,
            scalar_mu_Lambda=smith_mu_Lambda_scalar),
    Masking(REFERENCE, "Smith integral (numerical reference)",
            "G1 = μ / ∫ D(m)(ω·m)⁺ dm by Gauss quadrature (Heitz 2014, eq. 43), tabulated "
            "in a = 1/(α tanθ): the reference every closed form and approximation is "
            "checked against.",
            lambda ndf, w: mu_Lambda_smith_numeric(ndf, w),
            scalar_mu_Lambda=tabulated_mu_Lambda_masking_scalar, kernel_params=table_params),
    Masking("walter", "Walter rational fit",
            "Walter 2007's rational approximation of Beckmann's Λ (eq. 27), cheap, no erf.",
            walter_mu_Lambda, applies_to=("beckmann", "blinn_phong"), approximates="smith",
            scalar_mu_Lambda=walter_mu_Lambda_scalar, formula=WALTER),
    Masking("karis", "Karis",
            "G1 ≈ 2μ/(μ(2 − α) + α) (Karis 2013); identical to Schlick-GGX with k = α/2.",
            schlick_mu_Lambda(lambda a: 0.5 * a), applies_to=("ggx",), approximates="smith",
            simplifies_to=(({}, "schlick_ibl"),), scalar_mu_Lambda=half_alpha_mu_Lambda_scalar,
            formula=HALF_ALPHA),
    Masking("schlick_direct", "Schlick-GGX, direct light",
            "G1 = μ/(μ(1−k)+k), k = (r+1)²/8 with r = √α (Karis 2013, as in LearnOpenGL).",
            schlick_mu_Lambda(lambda a: (np.sqrt(a) + 1.0) ** 2 / 8.0), applies_to=("ggx",),
            approximates="smith", scalar_mu_Lambda=schlick_direct_mu_Lambda_scalar,
            formula=SCHLICK_DIRECT),
    Masking("schlick_ibl", "Schlick-GGX, image-based light",
            "G1 = μ/(μ(1−k)+k), k = r²/2 = α/2 (Karis 2013).",
            schlick_mu_Lambda(lambda a: 0.5 * a), applies_to=("ggx",), approximates="smith",
            scalar_mu_Lambda=half_alpha_mu_Lambda_scalar, formula=HALF_ALPHA),
]:
    MASKINGS.register(_m)


def G1(mu, mu_Lambda):
    """G1 = 1/(1+Λ) = μ/(μ + μΛ); 0 at μ ≤ 0 (the χ⁺ of Heitz 2014, eq. 43)."""
    mu = np.asarray(mu, dtype=float)
    return where_valid(mu > 0, [mu, mu_Lambda], lambda m, ml: m / (m + ml), 0.0)
