"""GGX and Beckmann against 50-digit references at the numerically worst points.

The references are the closed forms, written here again in mpmath from the papers
(not from app/): Walter et al. 2007 eq. 33-34 (GGX), eq. 25-27 (Beckmann), Heitz 2014
eq. 85-86 (anisotropic forms), eq. 99 (height-correlated G2), Schlick 1994. Inputs are
the exact float64 directions the code receives, so any difference is the code's
rounding — or a wrong branch.

Worst points: α down to 1e-4 (D ~ 3e7 at the peak, Λ from a = μ/s ~ 1e11), θ down to
1e-7° and up to 89.9999° (1 − μ and μ both lose digits), anisotropy 1e-4 : 1, the
specular peak (h = n) and just off it, Beckmann's erfc at large a (cancellation in
erf(a) − 1 if written naively).
"""
from __future__ import annotations

import itertools

import mpmath as mp
import numpy as np
import pytest

from app.model import make_spec

mp.mp.dps = 50

#: float64 has 2.2e-16; the formulas take a few dozen operations, and Beckmann's
#: exp(−tan²θ/α²) amplifies the rounding of its argument (measured worst: 1e-13 for
#: Beckmann's D and f, 1e-15 for the rest). A wrong branch or a cancellation shows up at
#: 1e-4 or worse.
RTOL = 1e-12
#: Λ and D may underflow to 0 where the reference is ~1e-320 (Beckmann's exp(−a²)):
#: that is the correct float64 value.
ATOL = 1e-290

ALPHAS = [(1e-4, 1e-4), (1e-3, 1e-3), (1.0, 1.0), (1e-4, 1.0), (0.3, 0.03)]
THETAS = [1e-7, 1e-3, 45.0, 89.99, 89.9999]


def direction(theta_deg, phi_deg):
    t, p = np.deg2rad(theta_deg), np.deg2rad(phi_deg)
    return np.array([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)])


def pairs():
    """(l, v): mirror pairs (h = n exactly: the peak), pairs 1e-6 rad off the mirror,
    and generic pairs; every θ against every θ."""
    out = []
    for tl, tv in itertools.product(THETAS, THETAS):
        out.append((direction(tl, 0.0), direction(tv, 180.0)))        # plane of incidence
        out.append((direction(tl, 30.0), direction(tv, 250.0)))       # off the plane
    for t in THETAS:
        out.append((direction(t, 10.0), direction(t, 190.0)))          # mirror: h = n
        out.append((direction(t, 10.0), direction(t, 190.0 + 5.7e-5)))  # 1e-6 rad off it
    return out


PAIRS = pairs()


# ------------------------------------------------------------------ the references

def mp_vec(a):
    return [mp.mpf(float(x)) for x in a]


def half(l, v):
    s = [a + b for a, b in zip(l, v)]
    n = mp.sqrt(sum(x * x for x in s))
    return [x / n for x in s]


def D_ref(ndf, m, ax, ay):
    """Walter 2007 eq. 33 / 25 in Heitz 2014's anisotropic form (eq. 85, 83)."""
    mz = m[2]
    q = (m[0] / ax) ** 2 + (m[1] / ay) ** 2          # = tan²θ_m/α(φ)² · m_z²
    if ndf == "ggx":
        return 1 / (mp.pi * ax * ay * (mz * mz + q) ** 2)
    return mp.exp(-q / (mz * mz)) / (mp.pi * ax * ay * mz ** 4)


def Lambda_ref(ndf, w, ax, ay):
    """Walter 2007 eq. 34 / 27 with a = μ / (α(φ) sinθ) (Heitz 2014 eq. 86)."""
    s = mp.sqrt((ax * w[0]) ** 2 + (ay * w[1]) ** 2)
    a = w[2] / s
    if ndf == "ggx":
        return (-1 + mp.sqrt(1 + 1 / (a * a))) / 2
    return (mp.erf(a) - 1) / 2 + mp.exp(-a * a) / (2 * a * mp.sqrt(mp.pi))


def reference(ndf, ax, ay, l, v, f0=mp.mpf("0.04")):
    ax, ay = mp.mpf(ax), mp.mpf(ay)
    l, v = mp_vec(l), mp_vec(v)
    h = half(l, v)
    D = D_ref(ndf, h, ax, ay)
    Ll, Lv = Lambda_ref(ndf, l, ax, ay), Lambda_ref(ndf, v, ax, ay)
    vh = sum(a * b for a, b in zip(v, h))
    F = f0 + (1 - f0) * (1 - vh) ** 5                  # Schlick 1994, F90 = 1, p = 5
    G2 = 1 / (1 + Ll + Lv)                             # Heitz 2014 eq. 99
    return {"D": D, "Lambda_l": Ll, "G1_i": 1 / (1 + Ll), "G1_o": 1 / (1 + Lv),
            "G2": G2, "F": F, "f": D * F * G2 / (4 * l[2] * v[2])}


# ------------------------------------------------------------------------ the tests

@pytest.mark.parametrize("ndf", ["ggx", "beckmann"])
@pytest.mark.parametrize("ax, ay", ALPHAS, ids=[f"ax{a:g}-ay{b:g}" for a, b in ALPHAS])
def test_against_mpmath(ndf, ax, ay):
    spec = make_spec(ndf=ndf, alpha=ax, alpha_y=ay, g2="height_correlated", fresnel="schlick",
                     f0=0.04, f90=1.0)
    brdf = spec.brdf()
    l = np.array([p[0] for p in PAIRS])
    v = np.array([p[1] for p in PAIRS])
    got = brdf.evaluate(l, v, ("f", "D", "G1_i", "G1_o", "G2", "F"))
    got["Lambda_l"] = brdf.ndf.Lambda(l)
    for i, (li, vi) in enumerate(PAIRS):
        for q, r in reference(ndf, ax, ay, li, vi).items():
            r = float(r)
            assert abs(got[q][i] - r) <= RTOL * abs(r) + ATOL, (q, li, vi, got[q][i], r)


def test_beckmann_lambda_large_a_keeps_relative_precision():
    """Λ(a) ~ e^{−a²}/(4a³√π) for large a: erf(a) − 1 and the exponential term cancel
    to all but the last digits; computed as −erfc(a)/2 + … it must still carry its
    relative precision while it is a normal float (a up to ~26)."""
    ndf = make_spec(ndf="beckmann", alpha=0.01).brdf().ndf
    for a in (3.0, 8.0, 15.0, 25.0):
        theta = np.arctan(1.0 / (0.01 * a))             # a = 1 / (α tanθ)
        w = np.array([np.sin(theta), 0.0, np.cos(theta)])
        ref = float(Lambda_ref("beckmann", mp_vec(w), mp.mpf(0.01), mp.mpf(0.01)))
        assert ndf.Lambda(w[None])[0] == pytest.approx(ref, rel=1e-9), a
