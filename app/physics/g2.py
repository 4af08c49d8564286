"""Joint masking-shadowing G2 from G1 and μΛ (masking.py).

With a = μ(1 + Λ) = μ + μΛ and G1 = μ/a:

* separable                    G2 = G1(l) G1(v)
* direction-correlated         G2 = λ(φ) G1(l)G1(v) + (1 − λ(φ)) min(G1(l), G1(v))
* height-correlated            G2 = 1 / (1 + Λ(l) + Λ(v))
* height-direction-correlated  G2 = 1 / (1 + max(Λl, Λv) + λ(φ) min(Λl, Λv))
* Hammon (GGX, approximation)  G2/(4 μl μv) ≈ 0.5 / lerp(2 μl μv, μl + μv, α)

Each returns G2 and V = G2/(4 μ_l μ_v) in μ and μΛ only (never Λ = μΛ/μ): V stays finite
when one direction grazes, +inf where both do (but separable). ``scalar_V``: V for one
point, λ = λ(φ) given (0 for forms without ``needs_phi``). References: Heitz 2014, JCGT
3(2), eq. 98-99 and sec. 6; Ashikhmin, Premože, Shirley 2000 and van Ginneken, Stavridi,
Koenderink 1998 (λ(φ)); Hammon 2017, GDC, "PBR Diffuse Lighting for GGX+Smith Microsurfaces"."""
from __future__ import annotations

import math
from dataclasses import dataclass, field
from typing import Callable

import numpy as np

from .formula import Formula, scalar_function
from .numeric import where_valid
from .registry import Registry
from .scalar import scalar


def _ratio(num, den):
    """num/den where den > 0; where den = 0 the caller's quantity is 0 (for G2) ."""
    return where_valid(den > 0, [num, den], lambda n, d: n / d, 0.0)


def _visibility(den4):
    """V = 1/den4 where den4 > 0, +inf where it is 0 (a true divergence)."""
    return where_valid(den4 > 0, [den4], lambda d: 1.0 / d, np.inf)


# ------------------------------------------------------------------------- λ(φ)

@dataclass(frozen=True, eq=False)
class LambdaPhi:
    """A weight λ(φ) ∈ [0, 1) of the azimuth difference φ ∈ [0, π] (radians):
    0 at φ = 0 (l and v in the same azimuth: masking and shadowing fully correlated),
    growing towards 1 as they turn apart."""
    name: str
    label: str
    description: str
    fn: Callable  # φ (radians) -> λ(φ)
    reference: str = ""
    scalar_fn: Callable | None = None   # the same for one φ
    formula: Formula | None = None      # the one spelling of scalar_fn and the shaders' λ(φ)


def ashikhmin(phi):
    """λ(φ) = 1 − exp(−7.3 φ²) (Ashikhmin et al. 2000), as −expm1 for small φ."""
    phi = np.asarray(phi, dtype=float)
    return -np.expm1(-7.3 * phi * phi)


ASHIKHMIN = Formula("lambda_phi_ashikhmin", ("phi",), "-expm1(-7.3 * phi * phi)",
                    doc="λ(φ) = 1 − exp(−7.3 φ²) (Ashikhmin, Premože, Shirley 2000).")
ashikhmin_scalar = scalar_function(ASHIKHMIN, __name__, "ashikhmin_scalar", extra_args=())


def van_ginneken(phi):
    """λ(φ) = 4.41 φ / (4.41 φ + 1) (van Ginneken et al. 1998)."""
    x = 4.41 * np.asarray(phi, dtype=float)
    return x / (x + 1.0)


VAN_GINNEKEN = Formula("lambda_phi_van_ginneken", ("phi",), "x / (x + 1.0)", body=(("x", "4.41 * phi"),),
                       doc="λ(φ) = 4.41φ/(4.41φ + 1) (van Ginneken, Stavridi, Koenderink 1998).")
van_ginneken_scalar = scalar_function(VAN_GINNEKEN, __name__, "van_ginneken_scalar", extra_args=())


LAMBDA_PHIS: Registry[LambdaPhi] = Registry("lambda_phi")
for _lp in [
    LambdaPhi("ashikhmin", "Ashikhmin",
              "λ(φ) = 1 − exp(−7.3 φ²): reaches 0.9 at φ ≈ 32°.",
              ashikhmin, "Ashikhmin, Premože, Shirley 2000", ashikhmin_scalar, ASHIKHMIN),
    LambdaPhi("van_ginneken", "van Ginneken",
              "λ(φ) = 4.41φ/(4.41φ + 1): rises more slowly, 0.93 at φ = 180°.",
              van_ginneken, "van Ginneken, Stavridi, Koenderink 1998", van_ginneken_scalar,
              VAN_GINNEKEN),
]:
    LAMBDA_PHIS.register(_lp)


def lambda_phi_entry(fn: Callable | None) -> LambdaPhi | None:
    """The registered λ(φ) whose function is ``fn`` (None: the default one)."""
    if fn is None:
        return LAMBDA_PHIS[DEFAULT_LAMBDA_PHI]
    return next((lp for lp in LAMBDA_PHIS.values() if lp.fn is fn), None)

#: λ(φ) used when a direction-correlated form is given none.
DEFAULT_LAMBDA_PHI = "ashikhmin"


def _lambda(phi, lambda_phi):
    if phi is None:
        raise ValueError("this G2 form needs the azimuth difference phi of l and v")
    fn = lambda_phi if lambda_phi is not None else LAMBDA_PHIS[DEFAULT_LAMBDA_PHI].fn
    return fn(phi)


# ------------------------------------------------------------------------- forms

def separable(mu_l, mu_v, ml_l, ml_v, **_):
    """G2 = G1(l) G1(v), V = 1 / (4 (μ_l + μ_lΛ_l)(μ_v + μ_vΛ_v))."""
    a_l, a_v = mu_l + ml_l, mu_v + ml_v
    return _ratio(mu_l * mu_v, a_l * a_v), _visibility(4.0 * a_l * a_v)


def height_correlated(mu_l, mu_v, ml_l, ml_v, **_):
    """G2 = 1/(1 + Λ_l + Λ_v), times μ_l μ_v over itself:
    G2 = μ_l μ_v / (μ_l μ_v + μ_v·μ_lΛ_l + μ_l·μ_vΛ_v)."""
    den = mu_l * mu_v + mu_v * ml_l + mu_l * ml_v
    return _ratio(mu_l * mu_v, den), _visibility(4.0 * den)


def direction_correlated(mu_l, mu_v, ml_l, ml_v, *, phi=None, lambda_phi=None, **_):
    """G2 = λ G1(l)G1(v) + (1 − λ) min(G1(l), G1(v)), λ = λ(φ).

    With G1 = μ/a: G1(l)G1(v)/(μ_l μ_v) = 1/(a_l a_v), and since G1(l) ≤ G1(v) ⟺
    μ_l a_v ≤ μ_v a_l, min(G1(l), G1(v))/(μ_l μ_v) = 1/max(μ_v a_l, μ_l a_v). So

        V = λ/(4 a_l a_v) + (1 − λ)/(4 max(μ_v a_l, μ_l a_v)),   G2 = 4 μ_l μ_v V.

    The max is 0 only where both directions graze (a > 0 always): V = +inf there, since
    1 − λ > 0 mathematically for every φ ∈ [0, π] of both registered λ(φ) (even where it
    rounds to 0 in float, as Ashikhmin's does beyond φ ≈ 128°). G2 is 0 there.
    """
    lam = _lambda(phi, lambda_phi)
    mu_l, mu_v, ml_l, ml_v, lam = np.broadcast_arrays(*(np.asarray(x, dtype=float)
                                                        for x in (mu_l, mu_v, ml_l, ml_v, lam)))
    a_l, a_v = mu_l + ml_l, mu_v + ml_v
    big = np.maximum(mu_v * a_l, mu_l * a_v)
    V = where_valid(big > 0, [lam, a_l, a_v, big],
                    lambda w, al, av, b: 0.25 * (w / (al * av) + (1.0 - w) / b), np.inf)
    G2 = where_valid(big > 0, [lam, mu_l, mu_v, a_l, a_v, big],
                     lambda w, ul, uv, al, av, b: ul * uv * (w / (al * av) + (1.0 - w) / b), 0.0)
    return G2, V


def height_direction_correlated(mu_l, mu_v, ml_l, ml_v, *, phi=None, lambda_phi=None, **_):
    """G2 = 1/(1 + max(Λ_l, Λ_v) + λ min(Λ_l, Λ_v)), λ = λ(φ), times μ_l μ_v over
    itself. μ_l μ_v Λ_l = μ_v·μ_lΛ_l =: A and μ_l μ_v Λ_v = μ_l·μ_vΛ_v =: B, and Λ_l ≥ Λ_v
    ⟺ A ≥ B (compared without dividing by μ, which may be 0):

        G2 = μ_l μ_v / (μ_l μ_v + max(A, B) + λ min(A, B)),   V = 1/(4 × that denominator).

    λ = 1 gives the height-correlated form, λ = 0 gives min(G1(l), G1(v))."""
    lam = _lambda(phi, lambda_phi)
    A, B = mu_v * ml_l, mu_l * ml_v
    den = mu_l * mu_v + np.maximum(A, B) + lam * np.minimum(A, B)
    return _ratio(mu_l * mu_v, den), _visibility(4.0 * den)


def hammon(mu_l, mu_v, ml_l, ml_v, *, ndf=None, **_):
    """Hammon 2017: V ≈ 0.5 / lerp(2 μ_l μ_v, μ_l + μ_v, α), lerp(x0, x1, t) =
    (1 − t) x0 + t x1, α the isotropic GGX α; G2 = 4 μ_l μ_v V. It replaces each
    √(α² + (1 − α²)μ²) of the exact height-correlated GGX form by lerp(μ, 1, α); it is exact at α → 0
    (G2 = 1) and at α = 1 (both give 2 μ_l μ_v/(μ_l + μ_v)). μΛ is not used."""
    if ndf is None:
        raise ValueError("hammon needs the NDF (its α)")
    if not ndf.isotropic:
        raise ValueError(f"g2=hammon is for isotropic α only; got alpha={ndf.alpha_x:g}, "
                         f"alpha_y={ndf.alpha_y:g}")
    alpha = ndf.alpha_x
    mu_l, mu_v = np.broadcast_arrays(np.asarray(mu_l, dtype=float), np.asarray(mu_v, dtype=float))
    den = (1.0 - alpha) * 2.0 * mu_l * mu_v + alpha * (mu_l + mu_v)
    return _ratio(2.0 * mu_l * mu_v, den), _visibility(2.0 * den)


# ---- the one spelling of V for the kernels (scalar_V) and the shaders; +∞ where the
# denominator is 0 (both directions on the horizon), the limit the numpy forms return.
_V_ARGS = ("mu_l", "mu_v", "ml_l", "ml_v", "lam")
V_FORMULAS = {
    "separable": Formula(
        "V_separable", _V_ARGS, "sel(den > 0.0, 0.25 / den, INF())",
        body=(("den", "(mu_l + ml_l) * (mu_v + ml_v)"),),
        doc="Separable G2 = G1(l) G1(v) (Heitz 2014, eq. 98): V = 1/(4 a_l a_v), a = μ + μΛ."),
    "height_correlated": Formula(
        "V_height_correlated", _V_ARGS, "sel(den > 0.0, 0.25 / den, INF())",
        body=(("den", "mu_l * mu_v + mu_v * ml_l + mu_l * ml_v"),),
        doc="Height-correlated G2 = 1/(1 + Λ_l + Λ_v) (Heitz 2014, eq. 99): V = 1/(4(μ_l μ_v + μ_v μΛ_l + μ_l μΛ_v))."),
    "direction_correlated": Formula(
        "V_direction_correlated", _V_ARGS,
        "sel(big > 0.0, 0.25 * (lam / (a_l * a_v) + (1.0 - lam) / big), INF())",
        body=(("a_l", "mu_l + ml_l"), ("a_v", "mu_v + ml_v"), ("big", "max(mu_v * a_l, mu_l * a_v)")),
        doc="Direction-correlated G2 = λ G1(l)G1(v) + (1 − λ) min(G1(l), G1(v)) (Ashikhmin et al. 2000;\n"
            "Heitz 2014, sec. 6): V = λ/(4 a_l a_v) + (1 − λ)/(4 max(μ_v a_l, μ_l a_v))."),
    "height_direction_correlated": Formula(
        "V_height_direction_correlated", _V_ARGS, "sel(den > 0.0, 0.25 / den, INF())",
        body=(("A", "mu_v * ml_l"), ("B", "mu_l * ml_v"), ("den", "mu_l * mu_v + max(A, B) + lam * min(A, B)")),
        doc="Height-direction-correlated G2 = 1/(1 + max(Λ_l, Λ_v) + λ min(Λ_l, Λ_v)) (Heitz 2014, sec. 6)."),
    "hammon": Formula(
        "V_hammon", _V_ARGS, "sel(den > 0.0, 0.5 / den, INF())",
        body=(("den", "(1.0 - alpha) * 2.0 * mu_l * mu_v + alpha * (mu_l + mu_v)"),), p=("alpha",),
        doc="Hammon 2017 (GDC): V ≈ 0.5 / lerp(2 μ_l μ_v, μ_l + μ_v, α), isotropic GGX; an approximation."),
}
separable_V = scalar_function(V_FORMULAS["separable"], __name__, "separable_V")
height_correlated_V = scalar_function(V_FORMULAS["height_correlated"], __name__, "height_correlated_V")
direction_correlated_V = scalar_function(V_FORMULAS["direction_correlated"], __name__, "direction_correlated_V")
height_direction_correlated_V = scalar_function(V_FORMULAS["height_direction_correlated"], __name__,
                                                "height_direction_correlated_V")
hammon_V = scalar_function(V_FORMULAS["hammon"], __name__, "hammon_V")


def _no_params(ndf) -> tuple:
    return ()


@dataclass(frozen=True, eq=False)   # a registry entry: compared and hashed by identity
class G2Form:
    """A G2 form. ``approximates`` names the exact form this one approximates;
    ``scalar_V(μ_l, μ_v, μΛ_l, μΛ_v, λ, p)`` is V for one point, p = kernel_params(ndf)."""
    name: str
    label: str
    description: str
    G2_and_V: Callable  # (mu_l, mu_v, ml_l, ml_v, *, phi, ndf, lambda_phi) -> (G2, V)
    needs_phi: bool = False                     # takes φ and λ(φ) (LAMBDA_PHIS)
    applies_to: tuple[str, ...] | None = None   # NDF names; None = every NDF
    isotropic_only: bool = False                # rejects α_x ≠ α_y (ValueError)
    reference: str = ""
    approximates: str | None = None
    scalar_V: Callable | None = None
    kernel_params: Callable = field(default=_no_params)   # (ndf) -> floats
    formula: Formula | None = None    # the one spelling of scalar_V and the shaders' V

    @property
    def approximation(self) -> bool:
        return self.approximates is not None

    def exact(self) -> "G2Form":
        """The exact form this one stands for (itself when exact)."""
        return self if self.approximates is None else G2_FORMS[self.approximates].exact()


#: Every G2 form by name (``G2_FORMS.register(G2Form(...))``).
G2_FORMS: Registry[G2Form] = Registry("G2 form")
for _g in [
    G2Form("separable", "Separable",
           "G1(l)·G1(v): ignores the correlation of masking and shadowing.",
           separable, reference="Heitz 2014, eq. 98", scalar_V=separable_V, formula=V_FORMULAS['separable']),
    G2Form("height_correlated", "Height-correlated",
           "1/(1+Λ(l)+Λ(v)): the recommended form (Heitz 2014, eq. 99).",
           height_correlated, reference="Heitz 2014, eq. 99", scalar_V=height_correlated_V, formula=V_FORMULAS['height_correlated']),
    G2Form("direction_correlated", "Direction-correlated",
           "λ(φ)·G1(l)G1(v) + (1−λ(φ))·min(G1(l), G1(v)): min(G1) when l and v share "
           "an azimuth, separable as they turn apart.",
           direction_correlated, needs_phi=True,
           reference="Ashikhmin et al. 2000; Heitz 2014, sec. 6", scalar_V=direction_correlated_V, formula=V_FORMULAS['direction_correlated']),
    G2Form("height_direction_correlated", "Height-direction-correlated",
           "1/(1 + max(Λl, Λv) + λ(φ)·min(Λl, Λv)): height-correlated, and min(G1) "
           "when l and v share an azimuth.",
           height_direction_correlated, needs_phi=True,
           reference="Heitz 2014, sec. 6", scalar_V=height_direction_correlated_V, formula=V_FORMULAS['height_direction_correlated']),
    G2Form("hammon", "Hammon (approx.)",
           "Height-correlated GGX visibility approximated by 0.5/lerp(2μlμv, μl+μv, α); "
           "isotropic GGX only.",
           hammon, applies_to=("ggx",), isotropic_only=True, approximates="height_correlated",
           reference="Hammon 2017, GDC", scalar_V=hammon_V, formula=V_FORMULAS['hammon'],
           kernel_params=lambda ndf: (ndf.alpha_x,)),
]:
    G2_FORMS.register(_g)


def azimuth_difference(l, v) -> np.ndarray:
    """φ ∈ [0, π] between the projections of l and v on the tangent plane (0 where
    either is along n, where it is undefined and the direction-correlated forms reduce
    to min(G1) — the right limit, since G1 = 1 there)."""
    cross = l[..., 0] * v[..., 1] - l[..., 1] * v[..., 0]
    dot = l[..., 0] * v[..., 0] + l[..., 1] * v[..., 1]
    return np.arctan2(np.abs(cross), dot)


@scalar
def azimuth_difference_scalar(lx, ly, vx, vy):
    return math.atan2(abs(lx * vy - ly * vx), lx * vx + ly * vy)
