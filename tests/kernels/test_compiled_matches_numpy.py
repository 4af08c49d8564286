"""Every registered NDF, masking, G2 form (with each λ(φ)), Fresnel model and diffuse
model through the compiled loops, against the numpy path (BRDF.evaluate and the numpy
albedo integrand) to 1e-12 relative.

The loops compose components independently (each meets the others through a fixed
interface), and each distinct combination costs a compile (10-30 s on a cold numba
cache: CI's), so the cases are a covering design, not the product: every NDF with every
masking that applies to it (the pairs that interact: a numeric masking integrates the
NDF's own slopes), and in those same cases every G2 form and λ(φ), every Fresnel model
(Schlick at p = 5 and off it: two compiled branches) and every diffuse model at least
twice, with different NDFs; :func:`test_the_design_covers_every_registry_entry` fails when
an entry is added and not placed here. Directions include grazing (μ = 0 exactly), normal
incidence, l = v, l = −v (no half vector) and below the horizon; degrees in too.
"""
from __future__ import annotations

import os
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


#: (NDF, masking, G2, λ(φ), Fresnel, diffuse, Fresnel at its defaults): one case per
#: NDF × masking pair; G2, Fresnel and diffuse spread over them (each ≥ 2 times).
CASES = [
    ("ggx", "smith", "height_correlated", None, "schlick", "lambert", True),      # the page's default
    ("ggx", "smith_numeric", "height_direction_correlated", "van_ginneken", "conductor", "burley", False),
    ("ggx", "karis", "hammon", None, "schlick", "oren_nayar", False),
    ("ggx", "schlick_direct", "separable", None, "dielectric", "eon", False),
    ("ggx", "schlick_ibl", "direction_correlated", "ashikhmin", "none", "hammon", False),
    ("beckmann", "smith", "direction_correlated", "van_ginneken", "schlick", "burley", False),
    ("beckmann", "smith_numeric", "height_correlated", None, "none", "oren_nayar", False),
    ("beckmann", "walter", "separable", None, "conductor", "lambert", True),   # = test_lookup_...'s
    ("blinn_phong", "smith", "separable", None, "conductor", "hammon", False),
    ("blinn_phong", "smith_numeric", "height_correlated", None, "schlick", "eon", True),
    ("blinn_phong", "walter", "height_direction_correlated", "ashikhmin", "dielectric", "burley", False),
    ("exp_power", "smith", "height_direction_correlated", "van_ginneken", "schlick", "lambert", False),
    ("exp_power", "smith_numeric", "direction_correlated", "van_ginneken", "dielectric", "hammon", False),
    ("gtr", "smith", "direction_correlated", "ashikhmin", "conductor", "eon", False),
    ("gtr", "smith_numeric", "separable", None, "schlick", "oren_nayar", False),
    ("student_t", "smith", "height_direction_correlated", "ashikhmin", "none", "lambert", False),
    ("student_t", "smith_numeric", "height_correlated", None, "dielectric", "burley", False),
]


def _brdf(case, alpha=0.3, alpha_y=0.15, kd=0.4):
    ndf, masking, g2, lp, fresnel, diffuse, defaults = case
    if G2_FORMS[g2].isotropic_only:
        alpha_y = None
    cls = FRESNELS[fresnel]
    values = {p.name: p.default if defaults else p.lo + 0.37 * (p.hi - p.lo) for p in cls.params}
    d = DIFFUSES[diffuse]
    model = d(alpha=alpha, **{p.name: p.lo + 0.63 * (p.hi - p.lo) for p in d.params})
    return BRDF(_ndf(ndf, alpha, alpha_y), MASKINGS[masking], G2_FORMS[g2], cls(**values), kd,
                lambda_phi=LAMBDA_PHIS[lp].fn if lp else None, diffuse=model)


def _id(case):
    return "-".join(x for x in case[:6] if x) + ("" if case[6] else "-off")


def test_the_design_covers_every_registry_entry():
    """Every NDF × masking pair that applies is a case; every G2 form with every λ(φ) it
    takes, every Fresnel and every diffuse model in at least two cases with different NDFs
    (Schlick at p = 5 and off it)."""
    pairs = {(c[0], c[1]) for c in CASES}
    assert pairs == {(n, m) for n in NDFS for m, masking in MASKINGS.items()
                     if masking.applies_to is None or n in masking.applies_to}
    assert len(CASES) == len(pairs)
    for g, form in G2_FORMS.items():
        for lp in (LAMBDA_PHIS if form.needs_phi else [None]):
            assert len({c[0] for c in CASES if c[2] == g and c[3] == lp}) >= (1 if form.applies_to else 2), (g, lp)
    for column, registry in ((4, FRESNELS), (5, DIFFUSES)):
        for name in registry:
            assert len({c[0] for c in CASES if c[column] == name}) >= 2, name
    for defaults in (True, False):
        assert any(c[4] == "schlick" and c[6] == defaults for c in CASES)


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


def _direction_deg(theta_deg, phi_deg):
    """numpy's directions from degrees, exact 0 at θ = 90° (cos θ = sin(90° − θ))."""
    t, p = np.deg2rad(theta_deg), np.deg2rad(phi_deg)
    c = np.sin(np.deg2rad(90.0 - np.asarray(theta_deg, dtype=float)))
    return np.stack(np.broadcast_arrays(np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), c), axis=-1)


@pytest.mark.parametrize("case", CASES, ids=_id)
def test_f_matches_numpy(case):
    brdf = _brdf(case)
    kernel = kernels.compile_now(brdf, "f")
    assert kernel is not None, "every registered component has its scalar formula"
    l, v = _directions()
    _assert_close(kernel.f(brdf, l, v), brdf.evaluate(l, v, ("f",))["f"])
    # isotropic too, and small α
    iso = replace(brdf, ndf=_ndf(case[0], 0.02))
    _assert_close(kernels.f(iso, l, v), iso.evaluate(l, v, ("f",))["f"])
    # degrees in (the API's path): a grid of v for several l, φ beyond ±360°, θ = 0 and 90°
    # (no φ_v = φ_l + 180° at θ = 90°: there the loop's l = −v is exact, numpy's radians not)
    th_l, th_v = np.linspace(0.0, 90.0, 7), np.linspace(0.0, 90.0, 11)
    phi_v = np.linspace(-180.0, 540.0, 29)
    got = kernels.f_deg(brdf, th_l[:, None, None], 30.0, th_v[None, :, None], phi_v)
    L, V = np.broadcast_arrays(_direction_deg(th_l, 30.0)[:, None, None, :],
                               _direction_deg(th_v[:, None], phi_v[None, :])[None])
    _assert_close(got.ravel(), brdf.evaluate(L, V, ("f",))["f"].ravel())


@pytest.mark.parametrize("case", CASES, ids=_id)
def test_albedo_integrand_matches_numpy(case):
    brdf = replace(_brdf(case, alpha=0.4, alpha_y=0.2), kd=0.0)
    assert kernels.compile_now(brdf, "albedo") is not None
    mu = np.array([0.0, 1e-3, 0.2, 0.7, 1.0])
    v = np.stack([np.sqrt(1 - mu * mu), np.zeros_like(mu), mu], axis=-1)
    compiled = albedo_module._integrate_order(brdf, v, 48)
    with kernels.disabled():
        reference = albedo_module._integrate_order(brdf, v, 48)
    _assert_close(compiled, reference)


def test_two_lobes_and_compensation_through_kernels_f():
    base = _brdf(CASES[0])
    two = replace(base, lobe2=_ndf("ggx", 0.7, 0.5), lobe_mix=0.3)
    comp = CompensatedBRDF(**{f: getattr(two, f) for f in two.__dataclass_fields__},
                           multiscatter=lambda a, b: 0.01 * (1 - a) * (1 - b))
    l, v = _directions()
    assert kernels.compile_now(base, "f") is not None
    for brdf in (two, comp):
        _assert_close(kernels.f(brdf, l, v), brdf.evaluate(l, v, ("f",))["f"])


#: The check of :func:`test_lookup_never_compiles_in_the_caller`, in a process of its own
#: with an empty kernel directory: in a test worker the background thread first works
#: through every model the worker's earlier tests queued (160 s of the suite's time,
#: waiting). A compile writes the model's generated module there first (compose.py).
_LOOKUP_CHECK = """
import sys, time
import numpy as np
from app import kernels
from app.kernels import compose
from app.model import make_spec
brdf = make_spec(ndf="beckmann", masking="walter", g2="separable", fresnel="conductor").brdf()
def directions(n):
    z = np.random.default_rng(1).uniform(0.05, 1.0, (n, 2))
    phi = np.random.default_rng(2).uniform(0, 2 * np.pi, (n, 2))
    s = np.sqrt(1 - z * z)
    return [np.stack([s[:, i] * np.cos(phi[:, i]), s[:, i] * np.sin(phi[:, i]), z[:, i]], -1) for i in (0, 1)]
t0 = time.monotonic()
first = kernels.lookup(brdf, "f")
answered = time.monotonic() - t0
kernels.f(brdf, *directions(2000))       # a figure's worth of numpy work, twice
kernels.f(brdf, *directions(2000))
time.sleep(2.0)
written_in_passing = len(list(compose.kernel_dir().glob("brdf_kernel_*.py")))
work, spent = directions(200000), time.thread_time()
deadline = time.monotonic() + 600
while kernels.lookup(brdf, "f") is None and time.monotonic() < deadline:
    if time.thread_time() - spent < 2 * kernels.RENT_SECONDS:
        kernels.f(brdf, *work)           # a model in use: its numpy work pays the rent
    time.sleep(0.05)
print(first is None, answered, written_in_passing, kernels.lookup(brdf, "f") is not None)
"""


def test_lookup_never_compiles_in_the_caller(tmp_path):
    """A model asked for before its loops exist is answered by numpy (None here, at
    once); used in passing (two figures' worth of numpy work), nothing is compiled; once
    its numpy work reaches the rent, it is queued and the background thread makes it
    ready."""
    import subprocess
    import sys
    out = subprocess.run([sys.executable, "-c", _LOOKUP_CHECK], capture_output=True, text=True,
                         timeout=660, env={**os.environ, "BRDF_FAST": "1",
                                           "BRDF_KERNEL_DIR": str(tmp_path / "kernels")})
    assert out.returncode == 0, out.stderr
    first_none, answered, written, ready = out.stdout.split()
    assert first_none == "True" and float(answered) < 1.0      # no compiling in the caller
    assert written == "0"                                 # used in passing: no compile started
    assert ready == "True"
