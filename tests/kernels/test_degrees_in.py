"""The compiled loop with angles in degrees (app.quantities.evaluate's path) against the
numpy reference: BRDF.evaluate on directions that numpy builds from the same angles
(ω = (sinθ cosφ, sinθ sinφ, cosθ), written out here), to 1e-12 relative, for several
NDFs, every Fresnel model, a direction-correlated G2, a numeric masking, diffuse models,
anisotropic and isotropic α; angles random plus θ = 0, θ = 90° (grazing, both grazing), φ beyond ±360°
and broadcast shapes."""
from __future__ import annotations

import numpy as np
import pytest

from app import kernels, quantities
from app.model import make_spec

from .test_compiled_matches_numpy import CASES, _assert_close, _brdf, _id

pytestmark = pytest.mark.skipif(not kernels.ENABLED, reason="numba absent or BRDF_FAST=0")

#: cases of test_compiled_matches_numpy's design (their loops are compiled once for both):
#: the default model, anisotropic α, each Fresnel model, a direction-correlated G2, a
#: numeric masking and several diffuse models
MODELS = [CASES[0], CASES[1], CASES[4], CASES[5], CASES[11], CASES[16]]


def direction(theta_deg, phi_deg):
    """numpy's directions, exact 0 at θ = 90° as the API promises (cos θ = sin(90° − θ))."""
    t, p = np.deg2rad(theta_deg), np.deg2rad(phi_deg)
    c = np.sin(np.deg2rad(90.0 - np.asarray(theta_deg, dtype=float)))
    return np.stack(np.broadcast_arrays(np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), c), axis=-1)


def angles(n=3000, seed=5):
    rng = np.random.default_rng(seed)
    th_l, th_v = rng.uniform(0, 90, n), rng.uniform(0, 90, n)
    ph_l, ph_v = rng.uniform(-720, 720, n), rng.uniform(-720, 720, n)
    th_l[:40], th_v[20:60], th_l[60:80], th_v[70:90] = 90.0, 90.0, 0.0, 0.0
    ph_l[100:120], ph_v[110:130] = 360.0, -180.0
    ph_l[130:140], ph_v[130:140] = 0.0, 180.0           # l = -v where θ_l = θ_v
    th_v[130:140] = th_l[130:140]
    return th_l, ph_l, th_v, ph_v


def reference(brdf, th_l, ph_l, th_v, ph_v):
    l, v = np.broadcast_arrays(direction(th_l, ph_l), direction(th_v, ph_v))
    return brdf.evaluate(l, v, ("f",))["f"]


#: (α_x, α_y): anisotropic, and isotropic (the loop then turns both directions so that v is at
#: φ = 0, three sin/cos pairs instead of four) at a moderate and a sharp α, where f changes
#: fastest with the azimuths (the turn keeps φ_l − φ_v exact)
ALPHAS = [(0.25, 0.4), (0.25, 0.25), (0.02, 0.02)]


@pytest.mark.parametrize("alpha", ALPHAS, ids=lambda a: f"alpha={a[0]},{a[1]}")
@pytest.mark.parametrize("case", MODELS, ids=_id)
def test_degrees_in_matches_numpy(case, alpha):
    brdf = _brdf(case, alpha=alpha[0], alpha_y=alpha[1])
    assert kernels.compile_now(brdf, "f") is not None
    a = angles()
    got = kernels.f_deg(brdf, *a)
    assert got is not None
    _assert_close(got, reference(brdf, *a))
    # through the API's function, and broadcast: a grid of v for one l
    th, ph = np.linspace(0, 90, 31)[:, None], np.linspace(-360, 360, 47)[None, :]
    out = quantities.evaluate(brdf, 37.3, 12.0, th, ph, ("f",))["f"]
    assert out.shape == (31, 47)
    _assert_close(out, reference(brdf, 37.3, 12.0, th, ph))


def test_chunked_and_two_lobes(monkeypatch):
    """More pairs than one chunk, and a second lobe (blended as numpy blends it)."""
    monkeypatch.setattr(quantities, "FUSED_CHUNK", 1000)
    brdf = make_spec(ndf="ggx", alpha=0.2, alpha2=0.6, lobe_mix=0.3, fresnel="schlick").brdf()
    assert kernels.compile_now(brdf, "f") is not None
    a = angles()
    _assert_close(quantities.evaluate(brdf, *a, ("f",))["f"], reference(brdf, *a))


def test_sin_cos_in_degrees_exact_at_quadrants():
    """The loop's directions at multiples of 90° are exact (0 and ±1, no -0.0 height)."""
    brdf = make_spec(ndf="ggx", alpha=0.3, fresnel="schlick").brdf()   # CASES[0]'s loops
    assert kernels.compile_now(brdf, "f") is not None
    # both grazing, opposite azimuths 90° apart: +inf (height-correlated), as numpy's
    f = kernels.f_deg(brdf, np.array([90.0, 90.0]), np.array([0.0, 450.0]), np.array([90.0, 90.0]),
                      np.array([90.0, -270.0]))
    assert np.all(np.isinf(f)) and np.all(f > 0)
