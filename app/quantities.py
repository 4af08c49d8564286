"""The arrays behind each view: what a data endpoint returns and a figure draws.

One function per view; each evaluates only what its view shows. Angles arrive in
degrees (API units) and are converted here, once.
"""
from __future__ import annotations

import time

import numpy as np

from .integrate.albedo import albedo, albedo_average
from .physics.brdf import BRDF
from .physics.masking import G1
from .physics.vectors import direction_deg


def evaluate(brdf: BRDF, theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg, want) -> dict:
    """BRDF terms at direction pairs (i = light l, o = view v), broadcast together."""
    l = direction_deg(theta_i_deg, phi_i_deg)
    v = direction_deg(theta_o_deg, phi_o_deg)
    l, v = np.broadcast_arrays(l, v)
    return brdf.evaluate(l, v, want)


def ndf_curve(brdf: BRDF, phi_deg: float, n: int) -> dict:
    """D(θ_m) for θ_m = 0..90° (both ends) at azimuth φ."""
    theta = np.linspace(0.0, 90.0, n)
    return {"theta_deg": theta, "D": brdf.ndf.D(direction_deg(theta, phi_deg))}


def g1_curve(brdf: BRDF, phi_deg: float, n: int) -> dict:
    """Λ(θ_v) and G1(θ_v) = 1/(1+Λ) for θ_v = 0..90° at azimuth φ (Λ = +inf at 90°)."""
    theta = np.linspace(0.0, 90.0, n)
    w = direction_deg(theta, phi_deg)
    ml = brdf.masking.mu_Lambda(brdf.ndf, w)
    mu = w[..., 2]
    Lambda = np.divide(ml, mu, out=np.full_like(mu, np.inf), where=mu > 0)
    return {"theta_deg": theta, "Lambda": Lambda, "G1": G1(mu, ml)}


def lobe_curve(brdf: BRDF, theta_i_deg: float, phi_i_deg: float, n: int, cosine: bool) -> dict:
    """f in the plane of incidence, θ_o from −90° to 90°; θ_o > 0 on the mirror side
    (azimuth φ_i + 180°). ``cosine`` multiplies by cos θ_i."""
    theta_o = np.linspace(-90.0, 90.0, n)
    phi_o = np.where(theta_o >= 0, phi_i_deg + 180.0, phi_i_deg)
    f = evaluate(brdf, theta_i_deg, phi_i_deg, np.abs(theta_o), phi_o, ("f",))["f"]
    if cosine:
        return {"theta_o_deg": theta_o, "f_cos": f * np.sin(np.deg2rad(90.0 - theta_i_deg))}
    return {"theta_o_deg": theta_o, "f": f}


def lobe_grid(brdf: BRDF, theta_i_deg: float, phi_i_deg: float, n_theta: int, n_phi: int) -> dict:
    """f over the hemisphere of v: θ_v = 0..90° (n_theta), φ_v = 0..360° (n_phi)."""
    theta = np.linspace(0.0, 90.0, n_theta)
    phi = np.linspace(0.0, 360.0, n_phi)
    f = evaluate(brdf, theta_i_deg, phi_i_deg, theta[:, None], phi[None, :], ("f",))["f"]
    return {"theta_deg": theta, "phi_deg": phi, "f": f}


def albedo_curve(brdf: BRDF, mu, phi_deg: float, tol: float) -> dict:
    """E(μ) at the given cosines, E_avg over [0, 1], with errors and cost."""
    t0 = time.perf_counter()
    res = albedo(brdf, mu, np.deg2rad(phi_deg), tol)
    E_avg, E_avg_error, avg_evals = albedo_average(brdf, np.deg2rad(phi_deg), tol)
    return {
        "mu": res.mu, "E": res.E, "E_error": res.E_error,
        "E_avg": E_avg, "E_avg_error": E_avg_error,
        "method": "quadrature",
        "evaluations": res.evaluations + avg_evals,
        "seconds": time.perf_counter() - t0,
    }


def g2_grid(brdf: BRDF, phi_deg: float, n: int) -> dict:
    """G2(l, v) over θ_l, θ_v = 0..90° (n each; rows θ_l, columns θ_v), with l at
    azimuth 0 (along t, the direction of α_x) and v at azimuth φ: φ is the azimuth
    difference of the direction-correlated forms."""
    theta = np.linspace(0.0, 90.0, n)
    G2 = evaluate(brdf, theta[:, None], 0.0, theta[None, :], phi_deg, ("G2",))["G2"]
    return {"theta_l_deg": theta, "theta_v_deg": theta, "G2": G2}


def fresnel_curve(brdf: BRDF, n: int) -> dict:
    """F(θ) for θ = 0..90° (θ the angle between v and h), its cosine-weighted average,
    and — for an approximation (Schlick) — the exact form it stands for (the dielectric
    of the same F₀) and the error F − F_exact."""
    theta = np.linspace(0.0, 90.0, n)
    cos_theta = direction_deg(theta, 0.0)[..., 2]   # exactly 0 at 90°
    F = brdf.fresnel.F(cos_theta)
    out = {"theta_deg": theta, "F": F, "F_avg": brdf.fresnel.F_avg()}
    exact = brdf.fresnel.exact_counterpart()
    if exact is not None:
        F_exact = exact.F(cos_theta)
        out.update({"F_exact": F_exact, "F_error": F - F_exact,
                    "F_exact_model": {"fresnel": exact.name,
                                      **{p.name: getattr(exact, p.name) for p in exact.params}}})
    return out
