"""Disney BRDF Explorer `.brdf` files open and draw without edits (issue 33): our own files
in that format (tests/e2e/brdf/: the explorer's analytic models' physics, written in the
desktop-GLSL idioms its files use, none of its files copied) are picked through the
page's file input one after another in one page, compiled, drawn as a sphere with no
NaN/∞, measured with no NaN/∞ or negative value, and their f read back from the GPU
(measure.js's evaluator) equals numpy written here from each paper's formula.
"""
from __future__ import annotations

import numpy as np
import pytest

from tests.e2e.user_brdf_page import BRDF_DIR, LOADED, load_brdf, open_gpu_page

pytestmark = pytest.mark.e2e

HERE = BRDF_DIR
FILES = sorted(HERE.glob("*.brdf"))
#: float32 GPU against float64 numpy (the issue's bound for a BRDF against its twin)
REL = 1e-4
#: below FLOOR × the file's largest f at the pairs, a difference counts against that
#: floor: float32 exp/pow flush what is ~1e-38 to 0 where float64 keeps it (as measure.js)
FLOOR = 1e-6
#: pairs compared per file; θ ≤ 80° each way, seeded
PAIRS = 512
N, X, Y = np.array([0.0, 0.0, 1.0]), np.array([1.0, 0.0, 0.0]), np.array([0.0, 1.0, 0.0])


def _dirs(rng, count):
    mu = rng.uniform(np.cos(np.radians(80)), 1.0, count)
    phi = rng.uniform(0, 2 * np.pi, count)
    s = np.sqrt(1 - mu * mu)
    return np.stack([s * np.cos(phi), s * np.sin(phi), mu], axis=1)


def _frame(L, V):
    H = (L + V) / np.linalg.norm(L + V, axis=1, keepdims=True)
    d = lambda a, b: a @ b if b.ndim == 1 else np.sum(a * b, axis=1)   # noqa: E731
    return H, d


def _schlick(f0, c):
    """Schlick 1994 eq. 15."""
    return f0 + (1 - f0) * (1 - c) ** 5


def _fresnel_dielectric(c, eta):
    """Cook & Torrance 1982: unpolarised dielectric Fresnel, g = √(η² + c² − 1)."""
    g = np.sqrt(eta * eta + c * c - 1)
    return 0.5 * (g - c) ** 2 / (g + c) ** 2 * (1 + (c * (g + c) - 1) ** 2 / (c * (g - c) + 1) ** 2)


def walter(L, V, p):
    """Walter et al. 2007: GGX D (eq. 33), separable Smith G1 (eq. 34), exact F (eq. 22)."""
    H, d = _frame(L, V)
    a, nh = p["alpha"], d(H, N)
    D = a * a / (np.pi * nh ** 4 * (a * a + (1 - nh * nh) / (nh * nh)) ** 2)
    g1 = lambda c: 2 / (1 + np.sqrt(1 + a * a * (1 - c * c) / (c * c)))   # noqa: E731
    F = _fresnel_dielectric(d(V, H), p["eta"]) if p["useFresnel"] else 1.0
    return D * g1(d(L, N)) * g1(d(V, N)) * F / (4 * d(L, N) * d(V, N))


def cook_torrance(L, V, p):
    """Cook & Torrance 1982: Beckmann D (normalised, Walter 2007 eq. 25), V-cavity G (eq. 3), Schlick F."""
    H, d = _frame(L, V)
    m, nh, nl, nv, vh = p["m"], d(H, N), d(L, N), d(V, N), d(V, H)
    D = np.exp(-(1 - nh * nh) / (nh * nh * m * m)) / (np.pi * m * m * nh ** 4)
    G = np.minimum(1, np.minimum(2 * nh * nv / vh, 2 * nh * nl / vh))
    return D * G * _schlick(p["f0"], vh) / (4 * nl * nv)


def ashikhmin_shirley(L, V, p):
    """Ashikhmin & Shirley 2000: specular eq. 4 (exponent by cos²φ_h, sin²φ_h), diffuse eq. 5."""
    H, d = _frame(L, V)
    nu, nv_ = p["nu"], (p["nu"] if p["isotropic"] else p["nv"])
    nh, hk, nl, nv = d(H, N), d(H, V), d(L, N), d(V, N)
    phi_h = np.arctan2(d(H, Y), d(H, X))
    e = nu * np.cos(phi_h) ** 2 + nv_ * np.sin(phi_h) ** 2
    spec = np.sqrt((nu + 1) * (nv_ + 1)) / (8 * np.pi) * nh ** e / (hk * np.maximum(nl, nv)) * _schlick(p["Rs"], hk)
    diff = 28 * p["Rd"] / (23 * np.pi) * (1 - p["Rs"]) * (1 - (1 - nl / 2) ** 5) * (1 - (1 - nv / 2) ** 5)
    return spec + diff


def blinn_phong(L, V, p):
    """Blinn 1977, normalised as Real-Time Rendering 3rd ed. eq. 7.49: kd/π + ks (n+8)/(8π) (n·h)^n."""
    H, d = _frame(L, V)
    lobe = p["ks"] * (p["n"] + 8) / (8 * np.pi) * d(H, N) ** p["n"]
    return np.asarray(p["kd"])[None, :] / np.pi + lobe[:, None]


def ward(L, V, p):
    """Ward 1992 eq. 5a, half-vector form of Walter 2005."""
    H, d = _frame(L, V)
    ax, ay = p["alpha_x"], p["alpha_y"]
    lobe = np.exp(-((d(H, X) / ax) ** 2 + (d(H, Y) / ay) ** 2) / d(H, N) ** 2) / (4 * np.pi * ax * ay * np.sqrt(d(L, N) * d(V, N)))
    return np.asarray(p["rho_d"])[None, :] / np.pi + np.asarray(p["rho_s"])[None, :] * lobe[:, None]


def oren_nayar(L, V, p):
    """Oren & Nayar 1994 eq. 30, with the angles themselves (θ by arccos, φ by arctan2)."""
    s2 = np.radians(p["sigma"]) ** 2
    A, B = 1 - 0.5 * s2 / (s2 + 0.33), 0.45 * s2 / (s2 + 0.09)
    ti, tr = np.arccos(np.clip(L[:, 2], -1, 1)), np.arccos(np.clip(V[:, 2], -1, 1))
    dphi = np.arctan2(L[:, 1], L[:, 0]) - np.arctan2(V[:, 1], V[:, 0])
    alpha, beta = np.maximum(ti, tr), np.minimum(ti, tr)
    return p["rho"] / np.pi * (A + B * np.maximum(0, np.cos(dphi)) * np.sin(alpha) * np.tan(beta))


def disney(L, V, p):
    """Burley 2012: diffuse §5.3, subsurface, GTR2 anisotropic (app. B.2) with Smith
    G1 (Heitz 2014 eq. 86), sheen, GTR1 clearcoat (eq. 4)."""
    H, d = _frame(L, V)
    nl, nv, nh, lh = d(L, N), d(V, N), d(H, N), d(L, H)
    lin = np.asarray(p["baseColor"]) ** 2.2
    lum = 0.3 * lin[0] + 0.6 * lin[1] + 0.1 * lin[2]
    tint = lin / lum
    w = lambda u: (1 - u) ** 5   # noqa: E731
    fd90 = 0.5 + 2 * p["roughness"] * lh * lh
    fd = (1 + (fd90 - 1) * w(nl)) * (1 + (fd90 - 1) * w(nv))
    fss90 = p["roughness"] * lh * lh
    fss = (1 + (fss90 - 1) * w(nl)) * (1 + (fss90 - 1) * w(nv))
    ss = 1.25 * (fss * (1 / (nl + nv) - 0.5) + 0.5)
    aspect = np.sqrt(1 - 0.9 * p["anisotropic"])
    ax, ay = max(0.001, p["roughness"] ** 2 / aspect), max(0.001, p["roughness"] ** 2 * aspect)
    D = 1 / (np.pi * ax * ay * ((d(H, X) / ax) ** 2 + (d(H, Y) / ay) ** 2 + nh * nh) ** 2)

    def g1(W, ax, ay):
        c = d(W, N)
        return 2 * c / (c + np.sqrt((d(W, X) * ax) ** 2 + (d(W, Y) * ay) ** 2 + c * c))

    f0 = (p["specular"] * 0.08 * ((1 - p["specularTint"]) + p["specularTint"] * tint)) * (1 - p["metallic"]) + lin * p["metallic"]
    Fs = f0[None, :] + (1 - f0[None, :]) * w(lh)[:, None]
    spec = (D * g1(L, ax, ay) * g1(V, ax, ay) / (4 * nl * nv))[:, None] * Fs
    sheen = (w(lh) * p["sheen"])[:, None] * ((1 - p["sheenTint"]) + p["sheenTint"] * tint)[None, :]
    a = 0.1 + (0.001 - 0.1) * p["clearcoatGloss"]
    Dc = (a * a - 1) / (np.pi * np.log(a * a) * (1 + (a * a - 1) * nh * nh))
    Fc = 0.04 + 0.96 * w(lh)
    coat = 0.25 * p["clearcoat"] * Dc * Fc * g1(L, 0.25, 0.25) * g1(V, 0.25, 0.25) / (4 * nl * nv)
    diffuse = (fd + p["subsurface"] * (ss - fd))[:, None] * lin[None, :] / np.pi
    return (diffuse + sheen) * (1 - p["metallic"]) + spec + coat[:, None]


def phong_lobe(L, V, p):
    """Phong 1975's lobe about the mirror of l, normalised (n + 2)/(2π) (Lewis 1994)."""
    R = 2 * (L @ N)[:, None] * N[None, :] - L
    D = np.maximum(0, np.sum(R * V, axis=1)) ** p["n"]
    return D * ((p["n"] + 2) / (2 * np.pi) if p["normalized"] else 1)


def schlick_smith(L, V, p):
    """Schlick 1994 eq. 19: G1(c) = c/(c − k c + k), k = m √(2/π)."""
    k = p["m"] * np.sqrt(2 / np.pi)
    g1 = lambda c: c / (c - k * c + k)   # noqa: E731
    G = g1(L @ N) * g1(V @ N)
    return G / ((L @ N) * (V @ N)) if p["includeInvNdotLNdotV"] else G


def d_ggx(L, V, p):
    """Walter et al. 2007 eq. 33, GGX D of the half vector alone (tan-free form)."""
    H, d = _frame(L, V)
    a2, nh = p["alpha"] ** 2, d(H, N)
    return np.where(nh > 0, a2 / (np.pi * (1 + (a2 - 1) * nh * nh) ** 2), 0.0)


def fresnel(L, V, p):
    H, d = _frame(L, V)
    return _fresnel_dielectric(d(L, H), p["ior"])


#: each file's f from its paper, by file name
REFERENCE = {"walter_ggx_dielectric.brdf": walter, "cook_torrance_beckmann.brdf": cook_torrance,
             "ashikhmin_shirley.brdf": ashikhmin_shirley, "blinn_phong_normalized.brdf": blinn_phong,
             "ward_anisotropic.brdf": ward, "oren_nayar.brdf": oren_nayar, "disney_principled_2012.brdf": disney,
             "d_phong_lobe.brdf": phong_lobe, "g_schlick_smith.brdf": schlick_smith, "f_dielectric_exact.brdf": fresnel,
             "d_ggx.brdf": d_ggx}


def test_every_file_has_its_reference():
    assert {f.name for f in FILES} == set(REFERENCE)


def test_disney_format_files_open_draw_and_equal_their_papers(page, page_log, shots):
    """All files in one page, picked one after another through the file input."""
    open_gpu_page(page, {"ndf": "ggx", "alpha": 0.3})
    rng = np.random.default_rng(33)
    L, V = _dirs(rng, PAIRS), _dirs(rng, PAIRS)
    # Oren-Nayar's reference goes through arccos (its θ); SwiftShader's acos is off by up to
    # ~1e-4, but the file itself uses no acos (it writes sin α, tan β from the cosines)
    failures = []
    for path in FILES:
        load_brdf(page, path, name=path.name)
        page.wait_for_function("(n) => window.__userBrdf.message.startsWith(n + ': ') && / parameters?;/.test(window.__userBrdf.message)",
                               arg=path.name, timeout=60_000)
        page.wait_for_function(LOADED, timeout=60_000)
        sphere = page.evaluate("() => window.__userBrdf.sphere()")
        assert sphere["nonFinite"] == 0 and sphere["lit"] > 0, (path.name, sphere)
        m = page.evaluate("() => window.__userBrdf.measure()")
        assert m["positivity"]["nonFinite"] == 0 and m["positivity"]["negative"] == 0, (path.name, m["positivity"])
        values = page.evaluate("() => window.__userBrdf.values")
        f = np.array(page.evaluate("([l, v]) => window.__userBrdf.evaluate(l, v)", [L.ravel().tolist(), V.ravel().tolist()]))
        gpu = f.reshape(-1, 4)[:, :3]
        ref = REFERENCE[path.name](L, V, values)
        ref = np.broadcast_to(ref[:, None] if ref.ndim == 1 else ref, gpu.shape)
        rel = np.abs(gpu - ref) / np.maximum(np.abs(ref), FLOOR * np.abs(ref).max())
        if not rel.max() <= REL:
            i = np.unravel_index(np.argmax(rel), rel.shape)
            failures.append(f"{path.name}: largest relative difference {rel.max():.2e} at pair {i[0]} "
                            f"(gpu {gpu[i]:.6g}, paper {ref[i]:.6g})")
        page.locator("#panel-gpu").screenshot(path=str(shots / f"gpu-brdf-{path.stem}.png"))
    assert not failures, "\n".join(failures)
    assert not page_log.problems()
