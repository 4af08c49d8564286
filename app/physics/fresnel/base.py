"""Fresnel reflectance F(cos θ_d), θ_d the angle between l (or v) and h: the interface.

Light arrives from outside (a medium of index 1, air). Every F is in [0, 1] and finite
for cos θ ∈ [0, 1]. A model is a :class:`Fresnel` subclass registered with
``@FRESNELS.register`` in its own module of this package; besides F it says whether it
is tabulated on the Schlick basis (:meth:`Fresnel.schlick_basis`), which exact form it
approximates, and writes F for one point (``F_scalar``, physics/scalar.py).

References
----------
Schlick 1994, "An Inexpensive BRDF Model for Physically-based Rendering", eq. 15;
Kulla & Conty 2017 (F̄); Born & Wolf, "Principles of Optics", sec. 1.5.2 and 14.2.
"""
from __future__ import annotations

from typing import ClassVar

import numpy as np

from ..formula import Formula, scalar_function
from ..numeric import where_valid
from ..params import Param
from ..registry import Registry
from ..scalar import scalar


def _cos(cos_theta) -> np.ndarray:
    """cos θ as float, clipped to [0, 1] (rounding of v·h may leave it just outside)."""
    return np.clip(np.asarray(cos_theta, dtype=float), 0.0, 1.0)


@scalar
def clip_cos_scalar(c):
    return min(max(c, 0.0), 1.0)


class Fresnel:
    name: ClassVar[str]
    label: ClassVar[str]
    description: ClassVar[str]
    reference: ClassVar[str] = ""
    params: ClassVar[tuple[Param, ...]] = ()
    menu_order: ClassVar[int] = 100
    #: The registered Fresnel this one approximates (see :meth:`exact`), or None.
    approximates: ClassVar[str | None] = None
    #: Parameter values at which this model is another registered one.
    simplifies_to: ClassVar[tuple[tuple[dict, str], ...]] = ()
    #: F for one point: F_scalar(cos θ_d, p), p = kernel_params(); None: numpy only.
    F_scalar = None
    #: F(c) written once (physics/formula.py), p = the parameters' names in order: the
    #: source of ``F_scalar`` and of the shaders' F; None: no kernel, no shader form.
    F_formula: ClassVar[Formula | None] = None

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        formula = cls.__dict__.get("F_formula")
        if formula is not None and "F_scalar" not in cls.__dict__:
            cls.F_scalar = staticmethod(scalar_function(formula, cls.__module__, f"{cls.__qualname__}.F_scalar"))

    def __init__(self, **values: float):
        for p in self.params:
            setattr(self, p.name, float(values.get(p.name, p.default)))

    def F(self, cos_theta_d) -> np.ndarray:
        raise NotImplementedError

    def F_avg(self) -> float:
        """Cosine-weighted hemispherical average F̄ = 2 ∫₀¹ F(μ) μ dμ (Kulla-Conty 2017),
        by a 64-point Gauss-Legendre rule in μ (F is smooth in μ for the exact forms);
        a closed form overrides this where one exists."""
        x, w = np.polynomial.legendre.leggauss(64)
        mu, w = 0.5 * (x + 1.0), 0.5 * w
        return float(2.0 * np.sum(self.F(mu) * mu * w))

    def schlick_basis(self) -> tuple[tuple[float, float | None], ...] | None:
        """F as Σ c · S_p with S_None = 1 and S_p = (1 − cos θ_d)^p, or None when F is not
        of that form. E is linear in F, so an albedo table per basis function serves
        every model of the form: E = Σ c E_p."""
        return None

    def exact_counterpart(self) -> "Fresnel | None":
        """The exact form this one approximates, with matching parameters, or None."""
        return None

    def exact(self) -> "Fresnel":
        """The exact form this one stands for (itself when exact)."""
        return self.exact_counterpart() or self

    def kernel_params(self) -> tuple[float, ...]:
        return tuple(getattr(self, p.name) for p in self.params)


#: Every Fresnel model by name, in menu order.
FRESNELS: Registry[type[Fresnel]] = Registry("Fresnel")
