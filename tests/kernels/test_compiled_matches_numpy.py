"""Every registered NDF, masking, G2 form (with each λ(φ)), and Fresnel model through
the compiled loops, against the numpy path (BRDF.evaluate and the numpy albedo
integrand) to 1e-12 relative.

The cases form a covering design over the registries: every NDF with every masking that
applies to it, every G2 form and λ(φ) with two NDFs, every Fresnel model with two NDFs
(the loops compose components independently, so each component meets the others'
common interface). Directions include grazing (μ = 0 exactly), normal incidence,
l = v, l = −v (no half vector) and below the horizon.
"""
from __future__ import annotations

import os
import time
from dataclasses import replace

import numpy as np
import pytest

from app import kernels
from app.integrate import albedo as albedo_module
from app.physics.brdf import BRDF, CompensatedBRDF
from app.physics.diffuse import DIFFUSES
from app.physics.fresnel import FRESNELS
from app.physics.g2 import G2_FORMS, LAMBDA_PHIS
from app.physics.masking import MASKINGS
from app.physics.ndf import NDFS

pytestmark = pytest.mark.skipif(not kernels.ENABLED, reason="numba absent or BRDF_FAST=0")

RTOL = 1e-12
SHAPES = {"gtr": {"gamma": 1.6}, "student_t": {"gamma": 2.7}, "exp_power": {"p": 0.6}}


def _ndf(name, alpha, alpha_y=None):
    cls = NDFS[name]
    return cls(alpha, alpha_y if cls.anisotropic else None, **SHAPES.get(name, {}))


def _cases():
    out = []
    for ndf in NDFS:
        for m, masking in MASKINGS.items():
            if masking.applies_to is None or ndf in masking.applies_to:
                out.append((ndf, m, "height_correlated", None, "schlick"))
    for g, form in G2_FORMS.items():
        for ndf in ("ggx", "beckmann"):
            if form.applies_to is not None and ndf not in form.applies_to:
                continue
            for lp in (LAMBDA_PHIS if form.needs_phi else [None]):
                out.append((ndf, "smith", g, lp, "schlick"))
    for fr in FRESNELS:
        for ndf in ("ggx", "student_t"):
            out.append((ndf, "smith", "separable", None, fr))
    return sorted(set(out), key=str)


CASES = _cases()


def _brdf(case, alpha=0.3, alpha_y=0.15, kd=0.1):
    ndf, masking, g2, lp, fresnel = case
    if G2_FORMS[g2].isotropic_only:
        alpha_y = None
    cls = FRESNELS[fresnel]
    # defaults (Schlick's p = 5 has its own branch), and off-default values elsewhere
    values = {p.name: p.default if g2 != "separable" else p.lo + 0.37 * (p.hi - p.lo)
              for p in cls.params}
    return BRDF(_ndf(ndf, alpha, alpha_y), MASKINGS[masking], G2_FORMS[g2], cls(**values), kd,
                lambda_phi=LAMBDA_PHIS[lp].fn if lp else None)


def _directions(n=400, seed=3):
    rng = np.random.default_rng(seed)
    w = rng.normal(size=(2, n, 3))
    w /= np.linalg.norm(w, axis=-1, keepdims=True)
    l, v = w[0], w[1]
    l[: n // 2, 2] = np.abs(l[: n // 2, 2])
    v[: n // 2, 2] = np.abs(v[: n // 2, 2])
    special = np.array([
        [[0.0, 0.0, 1.0], [0.0, 0.0, 1.0]],          # normal incidence, l = v
        [[1.0, 0.0, 0.0], [0.6, 0.8, 0.0]],          # both grazing
        [[1.0, 0.0, 0.0], [0.0, 0.6, 0.8]],          # one grazing
        [[0.6, 0.0, 0.8], [-0.6, 0.0, 0.8]],         # mirror pair
        [[0.6, 0.0, 0.8], [-0.6, 0.0, -0.8]],        # l = −v
        [[0.0, 0.6, 0.8], [0.0, 0.8, -0.6]],         # v below the horizon
    ])
    return np.concatenate([l, special[:, 0]]), np.concatenate([v, special[:, 1]])


def _assert_close(got, want):
    both_inf = np.isinf(got) & np.isinf(want)
    assert np.array_equal(np.isinf(got), np.isinf(want))
    g, w = got[~both_inf], want[~both_inf]
    assert np.all(np.abs(g - w) <= RTOL * np.abs(w) + 1e-300), \
        f"max relative error {np.max(np.abs(g - w) / np.maximum(np.abs(w), 1e-300)):.2e}"


@pytest.mark.parametrize("case", CASES, ids=lambda c: "-".join(x for x in c if x))
def test_f_matches_numpy(case):
    brdf = _brdf(case)
    kernel = kernels.compile_now(brdf)
    assert kernel is not None, "every registered component has its scalar formula"
    l, v = _directions()
    _assert_close(kernel.f(brdf, l, v), brdf.evaluate(l, v, ("f",))["f"])
    # isotropic too, and small α
    iso = replace(brdf, ndf=_ndf(case[0], 0.02))
    _assert_close(kernels.f(iso, l, v), iso.evaluate(l, v, ("f",))["f"])


@pytest.mark.parametrize("diffuse", list(DIFFUSES))
def test_every_diffuse_model_matches_numpy(diffuse):
    """Every diffuse model (its parameters off their defaults, ρ = kd = 0.7) in the
    compiled loops, with an isotropic and an anisotropic specular lobe, directions and
    degrees in."""
    cls = DIFFUSES[diffuse]
    model = cls(alpha=0.3, **{p.name: p.lo + 0.63 * (p.hi - p.lo) for p in cls.params})
    l, v = _directions()
    for brdf in (replace(_brdf(("ggx", "smith", "height_correlated", None, "schlick"), kd=0.7), diffuse=model),
                 replace(_brdf(("beckmann", "smith", "separable", None, "conductor"), kd=0.7), diffuse=model)):
        kernel = kernels.compile_now(brdf)
        assert kernel is not None, "every diffuse model has its formula"
        _assert_close(kernel.f(brdf, l, v), brdf.evaluate(l, v, ("f",))["f"])
    th_l, th_v = np.linspace(0.0, 90.0, 19), np.linspace(0.0, 90.0, 23)
    phi_v = np.linspace(-180.0, 540.0, 29)
    got = kernels.f_deg(brdf, th_l[:, None, None], 30.0, th_v[None, :, None], phi_v)
    l = np.stack([np.sin(np.deg2rad(th_l)) * np.cos(np.deg2rad(30.0)), np.sin(np.deg2rad(th_l)) * np.sin(np.deg2rad(30.0)),
                  np.sin(np.deg2rad(90.0 - th_l))], axis=-1)[:, None, None, :]
    t, p = np.deg2rad(th_v)[:, None], np.deg2rad(phi_v)[None, :]
    v = np.stack(np.broadcast_arrays(np.sin(t) * np.cos(p), np.sin(t) * np.sin(p),
                                     np.sin(np.deg2rad(90.0 - th_v))[:, None]), axis=-1)[None]
    l, v = np.broadcast_arrays(l, v)
    _assert_close(got.ravel(), brdf.evaluate(l, v, ("f",))["f"].ravel())


ALBEDO_CASES = [c for c in CASES if c[2] == "height_correlated" and c[4] == "schlick"] + \
    [c for c in CASES if c[0] == "ggx" and (c[2] != "height_correlated" or c[4] != "schlick")]


@pytest.mark.parametrize("case", ALBEDO_CASES, ids=lambda c: "-".join(x for x in c if x))
def test_albedo_integrand_matches_numpy(case):
    brdf = replace(_brdf(case, alpha=0.4, alpha_y=0.2), kd=0.0)
    assert kernels.compile_now(brdf) is not None
    mu = np.array([0.0, 1e-3, 0.2, 0.7, 1.0])
    v = np.stack([np.sqrt(1 - mu * mu), np.zeros_like(mu), mu], axis=-1)
    compiled = albedo_module._integrate_order(brdf, v, 48)
    with kernels.disabled():
        reference = albedo_module._integrate_order(brdf, v, 48)
    _assert_close(compiled, reference)


def test_two_lobes_and_compensation_through_kernels_f():
    base = _brdf(("ggx", "smith", "height_correlated", None, "schlick"))
    two = replace(base, lobe2=_ndf("ggx", 0.7, 0.5), lobe_mix=0.3)
    comp = CompensatedBRDF(**{f: getattr(two, f) for f in two.__dataclass_fields__},
                           multiscatter=lambda a, b: 0.01 * (1 - a) * (1 - b))
    l, v = _directions()
    assert kernels.compile_now(base) is not None
    for brdf in (two, comp):
        _assert_close(kernels.f(brdf, l, v), brdf.evaluate(l, v, ("f",))["f"])


#: The check of :func:`test_lookup_never_compiles_in_the_caller`, in a process of its own:
#: in a test worker the background thread first works through every model the worker's
#: earlier tests queued (160 s of the suite's time, waiting).
_LOOKUP_CHECK = """
import sys, time
from app import kernels
from app.model import make_spec
brdf = make_spec(ndf="beckmann", masking="walter", g2="separable", fresnel="conductor").brdf()
t0 = time.monotonic()
first = kernels.lookup(brdf)
answered = time.monotonic() - t0
deadline = time.monotonic() + 600
while kernels.lookup(brdf) is None and time.monotonic() < deadline:
    time.sleep(0.05)
print(first is None, answered, kernels.lookup(brdf) is not None)
"""


def test_lookup_never_compiles_in_the_caller():
    """A model asked for before its loops exist is answered by numpy (None here, at
    once) and queued; the background thread makes it ready."""
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", _LOOKUP_CHECK], capture_output=True, text=True,
                         timeout=660, env={**os.environ, "BRDF_FAST": "1"})
    assert out.returncode == 0, out.stderr
    first_none, answered, ready = out.stdout.split()
    assert first_none == "True" and float(answered) < 1.0      # no compiling in the caller
    assert ready == "True"
