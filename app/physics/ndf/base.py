"""The NDF interface, the slope-space base class and the NDF registry.

Everything a BRDF needs from an NDF is D(m) and μΛ(ω) — the Smith Λ times μ = cosθ,
which is finite everywhere (Λ itself diverges at grazing, μΛ tends to a constant).
G1, G2 and the BRDF are built from those in ``masking.py`` and ``brdf.py``, as pbrt-v4
builds them from ``Lambda``. Each NDF also writes its formulas for one point
(``*_scalar``, see ``physics/scalar.py``), which app/kernels compiles.

References
----------
Heitz 2014, "Understanding the Masking-Shadowing Function in Microfacet-Based BRDFs",
JCGT 3(2), sections 3-5.
"""
from __future__ import annotations

from typing import Callable, ClassVar

import numpy as np

from ..formula import Formula, scalar_function
from ..numeric import where_valid
from ..params import Param
from ..registry import Registry

ALPHA = Param(
    "alpha", "α (roughness, x)", 1e-4, 1.0, 0.3,
    "Microfacet roughness α of the formulas (α_x when anisotropic); α = r² for "
    "perceptual roughness r.", scale="log")
ALPHA_Y = Param(
    "alpha_y", "α_y (roughness, y)", 1e-4, 1.0, 0.3,
    "Roughness along the bitangent y; absent means isotropic (α_y = α).", scale="log")


class NDF:
    """A normal distribution function bound to its parameters.

    Subclasses set the class attributes and implement :meth:`D` and :meth:`mu_Lambda`,
    and register with ``@NDFS.register``.
    """

    name: ClassVar[str]
    label: ClassVar[str]
    description: ClassVar[str]
    reference: ClassVar[str]
    shape_params: ClassVar[tuple[Param, ...]] = ()
    menu_order: ClassVar[int] = 100  # position in menus; lower first
    #: False where ``Lambda`` is an approximation of the NDF's own Smith Λ (Blinn-Phong
    #: uses Walter's Beckmann substitution): the exact-Smith identities then hold only
    #: with masking=smith_numeric.
    smith_exact: ClassVar[bool] = True
    anisotropic: ClassVar[bool] = True
    #: Parameter values at which this NDF is another registered one:
    #: ((shape values, NDF name), ...), e.g. GTR at γ = 2 is GGX.
    simplifies_to: ClassVar[tuple[tuple[dict, str], ...]] = ()
    #: ``sample_visible(v, u) -> m``: visible normals with density G1(v)(v·m)⁺D(m)/(n·v)
    #: (Heitz 2014, eq. 38) for views v (k, 3) and primary samples u (n, 3); None where
    #: no sampler is known (a vndf request is then refused).
    sample_visible: ClassVar[Callable | None] = None

    def __init__(self, alpha: float, alpha_y: float | None = None, **shape: float):
        self.alpha_x = float(alpha)
        self.alpha_y = float(alpha if alpha_y is None else alpha_y)
        names = {p.name for p in self.shape_params}
        if set(shape) - names:
            raise TypeError(f"{self.name} takes no parameter(s) {sorted(set(shape) - names)}")
        for p in self.shape_params:
            setattr(self, p.name, float(shape.get(p.name, p.default)))

    @property
    def isotropic(self) -> bool:
        return self.alpha_x == self.alpha_y

    def D(self, m) -> np.ndarray:
        """D(m), normalised so that ∫ D(m)(n·m) dm = 1; 0 for n·m < 0."""
        raise NotImplementedError

    def mu_Lambda(self, w) -> np.ndarray:
        """μ Λ(ω) for n·ω = μ ≥ 0: finite everywhere, 0 at normal incidence."""
        raise NotImplementedError

    def Lambda(self, w) -> np.ndarray:
        """Smith Λ(ω) (Heitz 2014, eq. 43); +inf at μ = 0, where it truly diverges."""
        mu = np.asarray(w)[..., 2]
        return where_valid(mu > 0, [self.mu_Lambda(w), mu], lambda ml, m: ml / m, np.inf)

    def __repr__(self) -> str:
        shape = "".join(f", {p.name}={getattr(self, p.name):g}" for p in self.shape_params)
        return f"{type(self).__name__}(alpha_x={self.alpha_x:g}, alpha_y={self.alpha_y:g}{shape})"


class SlopeSpaceNDF(NDF):
    """An NDF written in α-stretched slope space (Heitz 2014, sec. 5).

    D(m) = P22(x̃, ỹ) / (α_x α_y cos⁴θ_m), x̃ = −m_x/(α_x m_z), ỹ = −m_y/(α_y m_z); Smith's
    Λ(ω) depends on μ and s = α(φ) sinθ (``stretched_sin``; a = μ/s). Subclasses give, in
    q² = m_x²/α_x² + m_y²/α_y² (r̃² = q²/m_z²) and in (μ, s):

    * ``_D(mz, q2)``: α_x α_y D, for m_z ≥ 0, including its limit at m_z = 0;
    * ``_mu_Lambda(mu, s)``: μΛ, finite for μ ≥ 0, s ≥ 0, μ² + s² > 0;
    * ``radial_ccdf(r2)`` / ``radial_ccdf_inv(v)``: the tail mass 1 − C(r̃) beyond r̃ and its
      inverse (giving r̃²), precise at 1e-30, for the albedo, the Smith integral and sampling;
      ``radial_cdf``/``radial_cdf_inv`` follow (override where a form avoids cancellation).

    When ``shape_invariant`` (GGX, Beckmann, Student-t, exponential power) these do not depend
    on α and anisotropy is the stretch; otherwise the NDF is isotropic (α_x = α_y) and the
    methods may use α (GTR, Blinn-Phong). (derivation: docs/ndfs.md §1)"""

    shape_invariant: ClassVar[bool] = True

    @property
    def tail_beta(self) -> float:
        """β with r̃ ~ v^{−β} as the tail mass v = 1 − C(r̃) → 0 (½ for P22 ~ r̃^{−4},
        as GGX and GTR; 0 for exponential tails). Quadratures over v use it to choose
        their substitution."""
        return 0.5

    def __init__(self, alpha: float, alpha_y: float | None = None, **shape: float):
        super().__init__(alpha, alpha_y, **shape)
        if not self.shape_invariant and not self.isotropic:
            raise ValueError(f"{self.name} is not shape-invariant: it has no anisotropic form")

    def D(self, m):
        m = np.asarray(m, dtype=float)
        mz = m[..., 2]
        q2 = m[..., 0] ** 2 / self.alpha_x ** 2 + m[..., 1] ** 2 / self.alpha_y ** 2
        return where_valid(mz >= 0, [mz, q2], self._D, 0.0) / (self.alpha_x * self.alpha_y)

    def mu_Lambda(self, w):
        # Defined on the closed upper hemisphere; below it masking is 0 through χ⁺ and
        # μΛ is not used, so it is 0 there (and ω = −n never reaches 0/0).
        w = np.asarray(w, dtype=float)
        return where_valid(w[..., 2] >= 0, [w[..., 2], self.stretched_sin(w)], self._mu_Lambda, 0.0)

    def stretched_sin(self, w) -> np.ndarray:
        """s = √(α_x² ω_x² + α_y² ω_y²) = α(φ) sinθ."""
        w = np.asarray(w, dtype=float)
        return np.sqrt((self.alpha_x * w[..., 0]) ** 2 + (self.alpha_y * w[..., 1]) ** 2)

    def _D(self, mz, q2):
        raise NotImplementedError

    def _mu_Lambda(self, mu, s):
        raise NotImplementedError

    def radial_ccdf(self, r2):
        raise NotImplementedError

    def radial_ccdf_inv(self, v):
        raise NotImplementedError

    def radial_cdf(self, r2):
        return 1.0 - self.radial_ccdf(r2)

    def radial_cdf_inv(self, u):
        return self.radial_ccdf_inv(1.0 - np.asarray(u, dtype=float))

    # ---- the same formulas for one point (physics/scalar.py), p = kernel_params() ----
    # D_scalar(mz, q2, p): α_x α_y D (as _D); mu_Lambda_scalar(mu, s2, p): μΛ for μ ≥ 0
    # at s² = s2 ≥ 0 (0 at s = 0; s² given, as GGX's μΛ reads it, so that no square root
    # is taken only to be squared: 20 % of GGX's f a pair); radial_ccdf_scalar(r2, p), radial_cdf_inv_scalar(u, p),
    # radial_ccdf_inv_scalar(v, p). An NDF without them is served by numpy alone.
    D_scalar = mu_Lambda_scalar = None
    radial_ccdf_scalar = radial_cdf_inv_scalar = radial_ccdf_inv_scalar = None

    # ---- the one spelling (physics/formula.py) of D and μΛ for kernels and shaders ----
    #: α_x α_y D(mz, q2) for mz ≥ 0, its limit at mz = 0 included; p names bind
    #: kernel_params(). Given, it is the source of ``D_scalar`` and of the shaders' D.
    D_formula: ClassVar[Formula | None] = None
    #: μΛ(mu, s2), s2 = s²; given, the source of ``mu_Lambda_scalar`` and of the shaders' μΛ. None
    #: where μΛ needs what no shading language has (an incomplete beta or gamma function,
    #: a table of the Smith integral): the shaders then embed that table.
    mu_Lambda_formula: ClassVar[Formula | None] = None
    def __init_subclass__(cls, **kwargs):
        """Each declared formula becomes the ``*_scalar`` function the kernels compile
        (unless the class writes that function itself)."""
        super().__init_subclass__(**kwargs)
        for formula_attr, scalar_attr in (("D_formula", "D_scalar"), ("mu_Lambda_formula", "mu_Lambda_scalar")):
            formula = cls.__dict__.get(formula_attr)
            if formula is not None and scalar_attr not in cls.__dict__:
                setattr(cls, scalar_attr, staticmethod(
                    scalar_function(formula, cls.__module__, f"{cls.__qualname__}.{scalar_attr}")))

    def kernel_params(self) -> tuple[float, ...]:
        """The floats the scalar formulas read from ``p`` (α-dependent constants and
        shape parameters, tables where Λ is tabulated)."""
        return ()

    def radial_params(self):
        """The floats the radial scalar formulas (``radial_ccdf_scalar``,
        ``radial_ccdf_inv_scalar``) read: ``kernel_params`` up to any Λ table, which the
        compiled Smith-table build (smith_table.py) must not need."""
        return self.kernel_params()


# The shape-invariant NDFs are slope-space NDFs whose hooks ignore α.
ShapeInvariantNDF = SlopeSpaceNDF

#: Every NDF by name, in menu order: ``@NDFS.register`` on the class is all it takes to
#: appear in ``/api/v1/models``, the API and the page's menus.
NDFS: Registry[type[NDF]] = Registry("NDF")
