"""The diffuse models written again from their papers, in angles and explicit vectors
(not the package's (μ_l, μ_v, l·v) form), as the tests' independent references."""
from __future__ import annotations

import numpy as np


def direction(theta, phi):
    return np.stack([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi),
                     np.cos(theta) * np.ones_like(phi)], axis=-1)


def lambert(rho, theta_l, phi_l, theta_v, phi_v, **_):
    return rho / np.pi * np.ones(np.broadcast_shapes(*map(np.shape, (theta_l, phi_l, theta_v, phi_v))))


def burley(rho, theta_l, phi_l, theta_v, phi_v, roughness, **_):
    """Burley 2012, sec. 5.3: F_D90 = 0.5 + 2 roughness cos²θ_d, θ_d = angle(l, h)."""
    l, v = direction(theta_l, phi_l), direction(theta_v, phi_v)
    h = (l + v) / np.linalg.norm(l + v, axis=-1, keepdims=True)
    cos_d = np.sum(l * h, axis=-1)
    fd90 = 0.5 + 2.0 * roughness * cos_d ** 2
    return (rho / np.pi * (1 + (fd90 - 1) * (1 - np.cos(theta_l)) ** 5)
            * (1 + (fd90 - 1) * (1 - np.cos(theta_v)) ** 5))


def oren_nayar(rho, theta_l, phi_l, theta_v, phi_v, sigma, **_):
    """Oren & Nayar 1994, eq. 30 (qualitative model), in its own angles."""
    s2 = sigma ** 2
    A = 1 - 0.5 * s2 / (s2 + 0.33)
    B = 0.45 * s2 / (s2 + 0.09)
    alpha, beta = np.maximum(theta_l, theta_v), np.minimum(theta_l, theta_v)
    return rho / np.pi * (A + B * np.maximum(0, np.cos(phi_l - phi_v)) * np.sin(alpha) * np.tan(beta))


def fon(rho, theta_l, phi_l, theta_v, phi_v, r):
    """Fujii's Oren–Nayar as EON (Portsmouth et al. 2025) states it, s and t from vectors."""
    l, v = direction(theta_l, phi_l), direction(theta_v, phi_v)
    s = np.sum(l * v, axis=-1) - l[..., 2] * v[..., 2]
    t = np.where(s > 0, np.maximum(l[..., 2], v[..., 2]), 1.0)
    A = 1 / (1 + (0.5 - 2 / (3 * np.pi)) * r)
    return rho / np.pi * A * (1 + r * s / t)


def e_fon(theta, r):
    """E_F(θ) = A (1 + r G/π), G = sin θ (θ − sin θ cos θ) + ⅔ tan θ (1 − sin³θ) − ⅔ sin θ."""
    A = 1 / (1 + (0.5 - 2 / (3 * np.pi)) * r)
    G = (np.sin(theta) * (theta - np.sin(theta) * np.cos(theta))
         + 2 / 3 * np.tan(theta) * (1 - np.sin(theta) ** 3) - 2 / 3 * np.sin(theta))
    return A * (1 + r * G / np.pi)


def eon(rho, theta_l, phi_l, theta_v, phi_v, diffuse_roughness, **_):
    r = diffuse_roughness
    A = 1 / (1 + (0.5 - 2 / (3 * np.pi)) * r)
    avg = A * (1 + (2 / 3 - 28 / (15 * np.pi)) * r)
    rho_ms = rho ** 2 * avg / (1 - rho * (1 - avg))
    f_ms = rho_ms / np.pi * (1 - e_fon(theta_l, r)) * (1 - e_fon(theta_v, r)) / (1 - avg)
    return fon(rho, theta_l, phi_l, theta_v, phi_v, r) + f_ms


def hammon(rho, theta_l, phi_l, theta_v, phi_v, alpha, **_):
    """Hammon 2017's shader, line by line (lerp(a, b, t) = a + t (b − a))."""
    L, V = direction(theta_l, phi_l), direction(theta_v, phi_v)
    H = (L + V) / np.linalg.norm(L + V, axis=-1, keepdims=True)
    NdotL, NdotV, NdotH = L[..., 2], V[..., 2], H[..., 2]
    facing = 0.5 + 0.5 * np.sum(L * V, axis=-1)
    rough = facing * (0.9 - 0.4 * facing) * ((0.5 + NdotH) / NdotH)
    smooth = 1.05 * (1 - (1 - NdotL) ** 5) * (1 - (1 - NdotV) ** 5)
    single = (smooth + alpha * (rough - smooth)) / np.pi
    multi = 0.1159 * alpha
    return rho * (single + rho * multi)


REFERENCES = {"lambert": lambert, "burley": burley, "oren_nayar": oren_nayar, "eon": eon,
              "hammon": hammon}
