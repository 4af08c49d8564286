"""Diffuse reflection f_d(ρ; l, v): the interface every diffuse model implements.

A model is a :class:`Diffuse` subclass registered with ``@DIFFUSES.register`` in its own
module of this package. Every model here is isotropic and depends on the directions only
through μ_l = n·l, μ_v = n·v and l·v (cos φ sin θ_l sin θ_v = l·v − μ_l μ_v), so one
signature serves numpy and the compiled loops (``f_scalar``, physics/scalar.py). ρ is
the model's albedo parameter (the BRDF's ``kd``): some models are not linear in it.

The directional albedo E_d(ρ, μ) = ∫ f_d μ_l dω_l is a closed form where the paper gives
one, else a Gauss-Legendre product rule split at the model's kinks (μ_l = μ_v and
cos φ = 0), with its error estimated from the rule at half the order.
"""
from __future__ import annotations

from typing import ClassVar

import numpy as np

from ..formula import Formula, scalar_function
from ..numeric import where_valid
from ..params import Param
from ..registry import Registry


class Diffuse:
    name: ClassVar[str]
    label: ClassVar[str]
    description: ClassVar[str]
    reference: ClassVar[str] = ""
    params: ClassVar[tuple[Param, ...]] = ()
    menu_order: ClassVar[int] = 100
    #: Takes the specular model's roughness (Burley: r = √α; Hammon: α).
    uses_specular_roughness: ClassVar[bool] = False
    #: f_d(ρ = 1) conserves energy: E_d(1, μ) = 1 for every μ (white furnace).
    conserves_energy: ClassVar[bool] = False
    #: f_d(ρ, μ_l, μ_v, l·v, p) for one point; None: numpy only.
    f_scalar = None
    #: f_d(rho, mu_l, mu_v, l_dot_v) written once (physics/formula.py), p = the names of
    #: ``kernel_params()``: the source of ``f_scalar`` and of the shaders' diffuse term.
    f_formula: ClassVar[Formula | None] = None

    def __init_subclass__(cls, **kwargs):
        super().__init_subclass__(**kwargs)
        formula = cls.__dict__.get("f_formula")
        if formula is not None and "f_scalar" not in cls.__dict__:
            cls.f_scalar = staticmethod(scalar_function(formula, cls.__module__, f"{cls.__qualname__}.f_scalar"))

    def __init__(self, alpha: float = 0.25, **values: float):
        self.alpha = float(alpha)
        for p in self.params:
            setattr(self, p.name, float(values.get(p.name, p.default)))

    def f(self, rho, mu_l, mu_v, l_dot_v) -> np.ndarray:
        """f_d for directions in the upper hemisphere (μ_l, μ_v ≥ 0), no cosine."""
        raise NotImplementedError

    def kernel_params(self) -> tuple[float, ...]:
        return tuple(getattr(self, p.name) for p in self.params)

    def albedo(self, rho, mu) -> tuple[np.ndarray, float]:
        """(E_d(ρ, μ), error bound) at view cosines ``mu`` (quadrature by default)."""
        return albedo_quadrature(self, rho, mu)

    def albedo_avg(self, rho) -> tuple[float, float]:
        """E_avg = 2 ∫₀¹ E_d(ρ, μ) μ dμ and its error (Gauss-Legendre in μ)."""
        x, w = np.polynomial.legendre.leggauss(AVG_ORDER)
        mu, w = 0.5 * (x + 1.0), 0.5 * w
        E, error = self.albedo(rho, mu)
        return float(2.0 * np.sum(E * mu * w)), float(error)


#: Gauss-Legendre order per panel of the albedo rule (four panels in (μ_l, φ)); the error
#: is |E(ORDER) − E(ORDER/2)|, typically below 1e-8 for the kinked models.
ORDER = 48
#: Gauss-Legendre order of E_avg in μ (E_d is smooth in μ but for the kink at μ_l = μ_v).
AVG_ORDER = 32


def _panel_rule(a, b, order):
    x, w = np.polynomial.legendre.leggauss(order)
    half = 0.5 * (np.asarray(b, dtype=float) - np.asarray(a, dtype=float))
    return np.asarray(a, dtype=float)[..., None] + half[..., None] * (x + 1.0), half[..., None] * w


def _albedo_at_order(model: Diffuse, rho, mu, order: int) -> np.ndarray:
    """E_d by a product rule: μ_l on [0, μ_v] and [μ_v, 1], φ on [0, π/2] and [π/2, π]
    (f_d is even in φ, so the integral over [0, 2π] is twice that over [0, π])."""
    mu = np.atleast_1d(np.asarray(mu, dtype=float))
    total = np.zeros_like(mu)
    sin_v = np.sqrt(np.maximum(0.0, 1.0 - mu * mu))
    for lo, hi in ((np.zeros_like(mu), mu), (mu, np.ones_like(mu))):
        mu_l, w_mu = _panel_rule(lo, hi, order)                # (n, order)
        sin_l = np.sqrt(np.maximum(0.0, 1.0 - mu_l * mu_l))
        for phi_lo, phi_hi in ((0.0, 0.5 * np.pi), (0.5 * np.pi, np.pi)):
            phi, w_phi = _panel_rule(np.array(phi_lo), np.array(phi_hi), order)
            l_dot_v = (mu_l[..., :, None] * mu[:, None, None]
                       + sin_l[..., :, None] * sin_v[:, None, None] * np.cos(phi)[None, None, :])
            f = model.f(rho, mu_l[..., :, None], np.broadcast_to(mu[:, None, None], l_dot_v.shape),
                        l_dot_v)
            # f·μ_l = 0 on the horizon, also where f there is the +inf limit
            f_cos = np.where(mu_l[..., :, None] > 0, f, 0.0) * mu_l[..., :, None]
            total += 2.0 * np.einsum("nij,ni,j->n", f_cos, w_mu, w_phi)
    return total


def albedo_quadrature(model: Diffuse, rho, mu) -> tuple[np.ndarray, float]:
    E = _albedo_at_order(model, rho, mu, ORDER)
    coarse = _albedo_at_order(model, rho, mu, ORDER // 2)
    return E, float(np.max(np.abs(E - coarse), initial=0.0))


def times_rho(rho, g) -> np.ndarray:
    """ρ·g, 0 where ρ = 0 even where g is the +inf limit of both directions grazing."""
    return where_valid(np.asarray(rho) != 0, [rho, g], lambda r, x: r * x, 0.0)


def s_over_t(mu_l, mu_v, l_dot_v) -> np.ndarray:
    """max(0, cos φ) sin θ_max tan θ_min = max(0, s)/max(μ_l, μ_v), s = l·v − μ_l μ_v
    (Oren & Nayar 1994, eq. 30's geometric factor); +inf where both directions lie on
    the horizon and s > 0 (its limit along θ_l = θ_v → 90°)."""
    s = np.maximum(np.asarray(l_dot_v, dtype=float) - np.asarray(mu_l) * np.asarray(mu_v), 0.0)
    t = np.maximum(mu_l, mu_v)
    return where_valid(t > 0, [s, t], lambda a, b: a / b, np.where(s > 0, np.inf, 0.0))


def schlick_weight(mu) -> np.ndarray:
    """(1 − μ)⁵, the Schlick 1994 weight both Burley and Hammon use; μ clipped to [0, 1]."""
    return (1.0 - np.clip(mu, 0.0, 1.0)) ** 5


#: The arguments of every diffuse formula.
F_D_ARGS = ("rho", "mu_l", "mu_v", "l_dot_v")
#: (1 − μ)⁵ of a clipped μ, the Schlick weight of Burley and Hammon, as formula assignments.
def schlick_weight_body(mu: str, name: str) -> tuple[tuple[str, str], ...]:
    return ((f"{name}_x", f"1.0 - clamp({mu}, 0.0, 1.0)"),
            (name, f"{name}_x * {name}_x * {name}_x * {name}_x * {name}_x"))


#: Every diffuse model by name, in menu order.
DIFFUSES: Registry[type[Diffuse]] = Registry("diffuse model")
