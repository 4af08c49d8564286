"""The converged integrals behind every LUT, on texel centres and the midpoints between them.

A LUT of size n has texel centres x_i = (i + ½)/n on each axis (so no texel sits at μ = 0
or α = 0, where E has a corner). Values are computed on the refined grid of 2n − 1 points
per axis — centres and midpoints — so that a lookup between texels can be checked against
the integral itself: E(μ) by the project's adaptive quadrature (app/integrate/albedo.py)
to LUT_TOL, with its error bound, for F = 1 and for the Schlick basis (1 − v·h)^5
(Karis 2013), and E_avg by app/integrate/albedo.albedo_average.

Axes: roughness rows (``roughness``: α = r²; ``alpha``: α itself), μ columns (``mu``;
``sqrt_mu``: μ = x², denser at grazing).
"""
from __future__ import annotations

import time
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..errors import ParameterError, TooLarge
from ..integrate import budget
from ..integrate.albedo import albedo, albedo_average
from ..physics.brdf import BRDF
from ..physics.fresnel import FRESNELS
from ..physics.masking import MASKINGS, REFERENCE
from ..physics.ndf import ALPHA

#: Quadrature tolerance of each E node: below the float16 step at 1 (4.9e-4) and the
#: bilinear error of a 128² table (≳ 1e-5), above float32's 6e-8 (the table error says so).
LUT_TOL = 1e-6
SIZE_MIN, SIZE_MAX = 2, 256
MU_AXES = ("mu", "sqrt_mu")
ROUGHNESS_AXES = ("roughness", "alpha")
#: Schlick's exponent of the split-sum basis (Karis 2013; Filament's DFG)
SCHLICK_P = 5.0
#: builds kept per process (a 128² pair is ~0.5 MB)
CACHE_ENTRIES = 8


def centres(n: int) -> np.ndarray:
    return (np.arange(n) + 0.5) / n


def refined(n: int) -> np.ndarray:
    """Texel centres and the midpoints between neighbours: (k/2 + ½)/n, k = 0 … 2n − 2."""
    return (np.arange(2 * n - 1) / 2.0 + 0.5) / n


def alpha_of(axis: str, x):
    """α at axis value x, clamped to the explorer's smallest α (1e-4: r ≥ 0.01; only the
    first roughness texels of sizes above 50 are below it)."""
    x = np.asarray(x, dtype=float)
    return np.maximum(x * x if axis == "roughness" else x, ALPHA.lo)


def mu_of(axis: str, x):
    return np.asarray(x, dtype=float) ** 2 if axis == "sqrt_mu" else np.asarray(x, dtype=float)


@dataclass(frozen=True)
class LobeKey:
    """What a LUT depends on besides its axes: the NDF family and shape, masking, G2."""
    ndf_class: type
    shape: tuple
    masking: object
    g2: object
    lambda_phi: object

    @classmethod
    def of(cls, brdf: BRDF) -> "LobeKey":
        ndf = brdf.ndf
        check_masking(type(ndf), brdf.masking.name)
        shape = tuple((p.name, getattr(ndf, p.name)) for p in ndf.shape_params)
        return cls(type(ndf), shape, brdf.masking, brdf.g2, brdf.lambda_phi)

    def lobe(self, alpha: float, basis_p: float | None) -> BRDF:
        fresnel = FRESNELS["none"]() if basis_p is None else FRESNELS["schlick"](f0=0.0, f90=1.0, fresnel_p=basis_p)
        return BRDF(self.ndf_class(alpha, None, **dict(self.shape)), self.masking, self.g2, fresnel,
                    lambda_phi=self.lambda_phi)


def check_masking(ndf_class: type, masking: str) -> None:
    """A LUT is built for every masking whose Λ is the model's own: the exact Smith forms
    and the approximations engines ship (Schlick-GGX with k = α/2 for image-based light
    or k = (r + 1)²/8 for direct light, Karis 2013; Walter's fit). Refused (before any
    work) only where the model refuses Kulla-Conty too: an NDF without an exact Λ under
    masking=smith, which borrows another NDF's Λ (Walter's substitution for Blinn-Phong)."""
    entry = MASKINGS[masking]
    if entry.uses_ndf_Lambda and not ndf_class.smith_exact:
        raise ParameterError("masking", f"ndf={ndf_class.name} has no exact Smith Λ: masking={masking} "
                             f"substitutes another NDF's, whose albedo exceeds 1; give masking={REFERENCE} "
                             "(the Smith integral) or an approximation that applies to it")


@dataclass(frozen=True, eq=False)
class Grid:
    """E (or E_avg) and its error bound on the refined grid; rows roughness, columns μ."""
    values: np.ndarray
    error: np.ndarray
    seconds: float
    evaluations: int


def check_size(n: int) -> None:
    if not SIZE_MIN <= n <= SIZE_MAX:
        raise ParameterError("size", f"size must be an integer in [{SIZE_MIN}, {SIZE_MAX}]; got {n}")


def _refuse_if_slow(what: str, n: int, seconds_per_row: float, rows: int) -> None:
    b = budget.current()
    predicted = seconds_per_row * rows
    if b is not None and not b.affords(predicted):
        raise TooLarge("size", f"the {what} LUT of size {n} would take ~{predicted:.2g} s to compute, beyond "
                               f"this request's time budget (setting BRDF_MAX_SECONDS={b.seconds:g}); "
                               "ask a smaller size (builds are kept, so a size once built is instant), "
                               "or build it outside the server (python bench/lut.py)")


@lru_cache(maxsize=CACHE_ENTRIES)
def albedo_grid(key: LobeKey, n: int, mu_axis: str, roughness_axis: str, basis_p: float | None) -> Grid:
    """E(μ, α) on the refined grid, F = 1 (basis_p None) or the Schlick basis. Under a
    request's time budget, refused (TooLarge) after any row when the rest, predicted from
    the rows done, would not fit."""
    x = refined(n)
    mu = mu_of(mu_axis, x)
    values = np.empty((x.size, x.size))
    error = np.empty_like(values)
    evaluations, t0 = 0, time.perf_counter()
    for i, xr in enumerate(x):
        res = albedo(key.lobe(float(alpha_of(roughness_axis, xr)), basis_p), mu, tol=LUT_TOL)
        values[i], error[i] = res.E, res.E_error
        evaluations += res.evaluations
        _refuse_if_slow("E", n, (time.perf_counter() - t0) / (i + 1), x.size - i - 1)
    return Grid(values, error, time.perf_counter() - t0, evaluations)


@lru_cache(maxsize=CACHE_ENTRIES)
def average_grid(key: LobeKey, n: int, roughness_axis: str) -> Grid:
    """E_avg(α) = 2 ∫ E μ dμ (F = 1) on the refined roughness axis."""
    x = refined(n)
    values, error = np.empty(x.size), np.empty(x.size)
    evaluations, t0 = 0, time.perf_counter()
    for i, xr in enumerate(x):
        values[i], error[i], ev = albedo_average(key.lobe(float(alpha_of(roughness_axis, xr)), None), tol=LUT_TOL)
        evaluations += ev
        _refuse_if_slow("E_avg", n, (time.perf_counter() - t0) / (i + 1), x.size - i - 1)
    return Grid(values, error, time.perf_counter() - t0, evaluations)
