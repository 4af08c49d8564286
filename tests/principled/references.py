"""disney.brdf (Burley 2012's BRDF Explorer shader) transcribed line by line for one
point and one channel, as the tests' independent reference (local frame: N = +z,
X = +x, Y = +y; base colour linear, i.e. without mon2lin)."""
from __future__ import annotations

import math

import numpy as np

PI = math.pi


def mix(a, b, t):
    return a * (1 - t) + b * t


def schlick_fresnel(u):
    m = min(max(1 - u, 0.0), 1.0)
    return m ** 5


def gtr1(n_dot_h, a):
    if a >= 1:
        return 1 / PI
    a2 = a * a
    t = 1 + (a2 - 1) * n_dot_h * n_dot_h
    return (a2 - 1) / (PI * math.log(a2) * t)


def gtr2_aniso(n_dot_h, h_dot_x, h_dot_y, ax, ay):
    return 1 / (PI * ax * ay * ((h_dot_x / ax) ** 2 + (h_dot_y / ay) ** 2 + n_dot_h ** 2) ** 2)


def smith_g_ggx(n_dot_v, alpha_g):
    a, b = alpha_g * alpha_g, n_dot_v * n_dot_v
    return 1 / (n_dot_v + math.sqrt(a + b - a * b))


def smith_g_ggx_aniso(n_dot_v, v_dot_x, v_dot_y, ax, ay):
    return 1 / (n_dot_v + math.sqrt((v_dot_x * ax) ** 2 + (v_dot_y * ay) ** 2 + n_dot_v ** 2))


def disney(L, V, p, lobe="all"):
    """f (3 channels) at one pair of unit vectors; p holds the parameters by name."""
    L, V = np.asarray(L, float), np.asarray(V, float)
    n_dot_l, n_dot_v = L[2], V[2]
    if n_dot_l < 0 or n_dot_v < 0:
        return np.zeros(3)
    H = (L + V) / np.linalg.norm(L + V)
    n_dot_h, l_dot_h = H[2], float(L @ H)
    cd = np.asarray(p["base_color"], float)
    cdlum = 0.3 * cd[0] + 0.6 * cd[1] + 0.1 * cd[2]
    ctint = cd / cdlum if cdlum > 0 else np.ones(3)
    cspec0 = mix(p["specular"] * 0.08 * mix(np.ones(3), ctint, p["specular_tint"]), cd, p["metallic"])
    csheen = mix(np.ones(3), ctint, p["sheen_tint"])
    fl, fv = schlick_fresnel(n_dot_l), schlick_fresnel(n_dot_v)
    fd90 = 0.5 + 2 * l_dot_h * l_dot_h * p["roughness"]
    fd = mix(1.0, fd90, fl) * mix(1.0, fd90, fv)
    fss90 = l_dot_h * l_dot_h * p["roughness"]
    fss = mix(1.0, fss90, fl) * mix(1.0, fss90, fv)
    ss = 1.25 * (fss * (1 / (n_dot_l + n_dot_v) - 0.5) + 0.5)
    aspect = math.sqrt(1 - p["anisotropic"] * 0.9)
    ax = max(0.001, p["roughness"] ** 2 / aspect)
    ay = max(0.001, p["roughness"] ** 2 * aspect)
    ds = gtr2_aniso(n_dot_h, H[0], H[1], ax, ay)
    fh = schlick_fresnel(l_dot_h)
    fs = mix(cspec0, np.ones(3), fh)
    gs = smith_g_ggx_aniso(n_dot_l, L[0], L[1], ax, ay) * smith_g_ggx_aniso(n_dot_v, V[0], V[1], ax, ay)
    fsheen = fh * p["sheen"] * csheen
    dr = gtr1(n_dot_h, mix(0.1, 0.001, p["clearcoat_gloss"]))
    fr = mix(0.04, 1.0, fh)
    gr = smith_g_ggx(n_dot_l, 0.25) * smith_g_ggx(n_dot_v, 0.25)
    lobes = {"diffuse": (1 / PI) * mix(fd, ss, p["subsurface"]) * cd * (1 - p["metallic"]),
             "sheen": fsheen * (1 - p["metallic"]),
             "specular": gs * fs * ds,
             "clearcoat": 0.25 * p["clearcoat"] * gr * fr * dr * np.ones(3)}
    return sum(lobes.values()) if lobe == "all" else lobes[lobe]


DEFAULTS = dict(base_color=(0.82, 0.67, 0.16), metallic=0.0, specular=0.5, specular_tint=0.0,
                roughness=0.5, anisotropic=0.0, sheen=0.0, sheen_tint=0.5, clearcoat=0.0,
                clearcoat_gloss=1.0, subsurface=0.0)
