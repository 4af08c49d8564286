"""Directional albedo of the principled BRDF, lobe by lobe and channel by channel:
E_lobe,c(μ) = ∫ f_lobe,c(l, v) μ_l dω_l, so a stacked chart shows how much each lobe
reflects (:func:`albedo`), and what integrate/'s quadrature does not integrate itself
(:func:`rest_albedo`: it takes the specular lobes from PrincipledBRDF.lobes()). Each
lobe by the rule that suits it, each with its error:

* diffuse and sheen: colour × a scalar integral, by the diffuse registry's split
  Gauss-Legendre rule in (μ_l, φ) (physics/diffuse/base.py);
* specular: linear in F, so E_c = C_spec0,c E₁ + (1 − C_spec0,c) E_S with E₁ (F = 1) and
  E_S (F = (1 − cos θ_d)⁵) by the project's adaptive albedo quadrature (integrate/albedo.py),
  plus the per-channel Kulla-Conty albedo with that option;
* clearcoat: a Gauss rule over half vectors drawn from GTR1·cos (Burley 2012, appendix B's
  inverse CDF), where the integrand F·V·μ_l·4(v·h)/μ_h no longer holds the peak of D.
"""
from __future__ import annotations

import time

import numpy as np

from ..integrate.albedo import albedo as microfacet_albedo
from ..physics.diffuse.base import albedo_quadrature
from ..physics.fresnel import FRESNELS
from ..physics.masking import MASKINGS
from ..physics.ndf import NDFS
from . import lobes as L
from .colour import channel
from .params import LOBES

#: Gauss-Legendre nodes per panel of the clearcoat rule (u and two φ panels); its error
#: is the difference to the rule at half the order.
CLEARCOAT_ORDER = 96
#: Gauss-Legendre nodes in μ for E_avg = 2 ∫ E μ dμ.
AVG_NODES = 16


class _Scalar:
    """Adapter: a colourless lobe shape g(μ_l, μ_v, l·v) as a diffuse model's f."""
    def __init__(self, shape):
        self.shape = shape

    def f(self, rho, mu_l, mu_v, l_dot_v):
        return rho * self.shape(mu_l, mu_v, l_dot_v)


def _by_rule(shape, mu) -> tuple[np.ndarray, float]:
    return albedo_quadrature(_Scalar(shape), 1.0, mu)


def _diffuse(m, mu):
    colour = (1.0 - m.metallic) * m.base_linear
    # one channel at a time: the diffuse model need not be linear in ρ (EON)
    parts = [_by_rule(lambda a, b, c, rho=float(rho): L.diffuse_rho(m, rho, a, b, c), mu)
             for rho in colour]
    return np.stack([E for E, _ in parts], axis=-1), max(err for _, err in parts)


def _sheen(m, mu):
    if m.sheen == 0 or m.metallic == 1:
        return np.zeros((len(mu), 3)), 0.0
    E, err = _by_rule(lambda a, b, c: np.broadcast_to(L.schlick_weight(L.cos_theta_d(c)), np.shape(c)), mu)
    colour = (1.0 - m.metallic) * m.sheen * m.sheen_color
    return E[:, None] * colour, err * float(colour.max())


def _specular(m, mu, phi, tol):
    one = microfacet_albedo(m.specular_brdf(FRESNELS["none"]()), mu, phi, tol)
    s = microfacet_albedo(m.specular_brdf(FRESNELS["schlick"](f0=0.0, f90=1.0)), mu, phi, tol)
    c0 = m.specular_color
    E = one.E[:, None] * c0 + s.E[:, None] * (1.0 - c0)
    err = float(np.max(one.E_error) + np.max(s.E_error))
    if m.options["principled_multiscatter"] == "kulla_conty":
        E = E + np.stack([ms.albedo(mu) for ms in m.multiscatter()], axis=-1)
        err += max(ms.error for ms in m.multiscatter())
    return E, err


def _clearcoat_at(m, mu, order):
    a2 = m.clearcoat_ndf().alpha_x ** 2
    x, w = np.polynomial.legendre.leggauss(order)
    u, wu = 0.5 * (x + 1.0), 0.5 * w
    phis = np.concatenate([0.5 * np.pi * (x + 1.0), np.pi + 0.5 * np.pi * (x + 1.0)])
    wphi = np.concatenate([0.5 * np.pi * w] * 2) / (2.0 * np.pi)
    cos2 = (1.0 - a2 ** (1.0 - u)) / (1.0 - a2)          # GTR1's inverse CDF of cos²θ_h
    ct, st = np.sqrt(cos2), np.sqrt(1.0 - cos2)
    h = np.stack(np.broadcast_arrays(st[:, None] * np.cos(phis), st[:, None] * np.sin(phis),
                                     ct[:, None]), axis=-1)          # (order, 2·order, 3)
    sin_v = np.sqrt(1.0 - mu * mu)
    v = np.stack([sin_v, np.zeros_like(mu), mu], axis=-1)[:, None, None, :]
    vh = np.sum(v * h, axis=-1)
    l = 2.0 * vh[..., None] * h - v
    ok = (vh > 0) & (l[..., 2] > 0)
    ggx, mask = NDFS["ggx"](L.CLEARCOAT_MASKING_ALPHA, None), MASKINGS["smith"]
    l_safe = np.where(ok[..., None], l, [0.0, 0.0, 1.0])
    v_term = 0.25 / ((l_safe[..., 2] + mask.mu_Lambda(ggx, l_safe)) * (mu + mask.mu_Lambda(ggx, v[..., 0, 0, :]))[:, None, None])
    F = L.CLEARCOAT_F0 + (1.0 - L.CLEARCOAT_F0) * L.schlick_weight(np.clip(vh, 0.0, 1.0))
    g = np.where(ok, 0.25 * m.clearcoat * F * v_term * l_safe[..., 2] * 4.0 * vh / ct[None, :, None], 0.0)
    return np.einsum("nij,i,j->n", g, wu, wphi)


def _clearcoat(m, mu):
    if m.clearcoat == 0:
        return np.zeros((len(mu), 3)), 0.0
    E = _clearcoat_at(m, mu, CLEARCOAT_ORDER)
    err = float(np.max(np.abs(E - _clearcoat_at(m, mu, CLEARCOAT_ORDER // 2))))
    return E[:, None] * np.ones(3), err


def rest_albedo(brdf, mu) -> tuple[np.ndarray, float]:
    """(E(μ), error) in the drawn channel of the lobes drawn but the specular lobe's single
    scattering: diffuse, sheen, clearcoat, and the per-channel Kulla-Conty lobe (exact:
    its albedo is (1 − Ê)·E_ms's closed form, integrate/compensation.py). The errors are
    per-channel bounds, so any channel or the luminance (weights summing to 1) keeps them."""
    m = brdf.material
    mu = np.atleast_1d(np.asarray(mu, dtype=float))
    parts = {"diffuse": _diffuse, "sheen": _sheen, "clearcoat": _clearcoat}
    E, error = np.zeros_like(mu), 0.0
    for name, rule in parts.items():
        if brdf.lobe in ("all", name):
            rgb, err = rule(m, mu)
            E, error = E + channel(rgb, brdf.channel), error + err
    if brdf.lobe in ("all", "specular") and m.options["principled_multiscatter"] == "kulla_conty":
        ms = m.multiscatter()
        E = E + channel(np.stack([x.albedo(mu) for x in ms], axis=-1), brdf.channel)
        error += max(x.error for x in ms)
    return E, error


def lobe_albedo(m, mu, phi: float = 0.0, tol: float = 1e-4) -> dict:
    """{lobe: (E (n, 3), error)} for the view cosines ``mu`` at azimuth ``phi``."""
    mu = np.atleast_1d(np.asarray(mu, dtype=float))
    return {"diffuse": _diffuse(m, mu), "sheen": _sheen(m, mu),
            "specular": _specular(m, mu, phi, tol), "clearcoat": _clearcoat(m, mu)}


def albedo(brdf, mu, phi: float = 0.0, tol: float = 1e-4) -> dict:
    """The albedo view's answer for a PrincipledBRDF: E and E_avg of the lobe(s) and
    channel drawn, each lobe's E per channel (``lobes``), errors, seconds."""
    t0 = time.perf_counter()
    mu = np.atleast_1d(np.asarray(mu, dtype=float))
    x, w = np.polynomial.legendre.leggauss(AVG_NODES)
    nodes = 0.5 * (x + 1.0)
    parts = lobe_albedo(brdf.material, np.concatenate([mu, nodes]), phi, tol)
    shown = LOBES if brdf.lobe == "all" else (brdf.lobe,)
    rgb = sum(parts[k][0] for k in shown)
    error = sum(parts[k][1] for k in shown)
    E = channel(rgb, brdf.channel)
    E_avg = float(2.0 * np.sum(E[len(mu):] * nodes * 0.5 * w))
    return {"mu": mu, "E": E[:len(mu)], "E_error": np.full(len(mu), error), "E_rgb": rgb[:len(mu)],
            "E_avg": E_avg, "E_avg_error": error, "method": "principled_lobes", "channel": brdf.channel,
            "requested_method": "principled_lobes", "evaluations": 0,
            "lobes": {k: {"E_rgb": parts[k][0][:len(mu)], "E": channel(parts[k][0][:len(mu)], brdf.channel),
                          "E_error": parts[k][1],
                          "E_avg": float(2.0 * np.sum(channel(parts[k][0][len(mu):], brdf.channel)
                                                      * nodes * 0.5 * w))}
                      for k in LOBES},
            "seconds": time.perf_counter() - t0}
