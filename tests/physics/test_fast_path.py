"""The fused kernel of app/physics/fast.py against the reference numpy path of brdf.py.

The reference is BRDF.evaluate with the fast path switched off (``fast.disabled()``):
the composition of the small per-term functions that the identity tests check. The
kernel must reproduce it to 1e-12 relative everywhere — random pairs, the grazing and
degenerate ones where each limit lives (+inf, 0, kd/π), the Beckmann μΛ on both sides
of its series switch — and must decline every model it does not implement.
"""
from __future__ import annotations

import dataclasses

import numpy as np
import pytest

from app.physics import fast
from app.physics.brdf import BRDF
from app.physics.fresnel import FRESNELS
from app.physics.g2 import G2_FORMS
from app.physics.masking import MASKINGS
from app.physics.ndf import make_ndf
from app.physics.ndf.ggx import GGX

from .conftest import make_brdf, random_upper_directions

# Relative agreement with the reference: a few ulps per operation over ~40 operations,
# and ~1e-13 for the Beckmann μΛ below its series (see fast._beckmann_mu_lambda).
RTOL = 1e-12
# Below this, f is compared absolutely: a Beckmann D in the subnormal range (< 2.2e-308)
# has lost its relative precision in either path (the two divide by π α_x α_y at
# different steps, so one may even underflow to 0 where the other does not), and
# V ≤ ~1e8 carries that to f.
F_ABS = 1e-299

ALPHAS = [(1e-4, 1e-4), (1e-3, 1e-3), (0.05, 0.05), (0.3, 0.3), (1.0, 1.0),
          (0.05, 0.5), (1.0, 0.1)]
FRESNEL_CASES = [("none", {}), ("schlick", {}), ("schlick", {"f0": 0.9, "f90": 0.2}),
                 ("schlick", {"f0": 0.0, "f90": 1.0})]
if "fresnel_p" in {p.name for p in FRESNELS["schlick"].params}:
    FRESNEL_CASES.append(("schlick", {"f0": 0.3, "fresnel_p": 2.5}))


def kernel_f(brdf, l, v):
    """f from the kernel itself (not through the dispatcher), so that the test runs the
    kernel even where numba is absent (then as plain Python)."""
    args = fast.spec_args(brdf) if fast.enabled() else None
    if args is None:
        with _forced():
            args = fast.spec_args(brdf)
    assert args is not None, f"the kernel should cover {brdf}"
    return fast.evaluate_f(args, l, v)


class _forced:
    """Switch the fast path on (when numba is absent it is off by default)."""

    def __enter__(self):
        self.before, fast._enabled = fast._enabled, True

    def __exit__(self, *exc):
        fast._enabled = self.before


def reference_f(brdf, l, v):
    with fast.disabled():
        return brdf.evaluate(l, v, ("f",))["f"]


def fresnel_condition(brdf, l, v):
    """Relative error of F that any float implementation may make, |c F'(c)/F| · 4 eps
    with c = v·h computed to a few ulps: (1 − c)^p loses all its digits as c → 1 when
    F₀ = 0 (the problem's conditioning, not an error of either path)."""
    fr = brdf.fresnel
    if not hasattr(fr, "f0"):
        return 0.0
    p = getattr(fr, "fresnel_p", 5.0)
    s = np.asarray(l, float) + np.asarray(v, float)
    h = s / np.maximum(np.linalg.norm(s, axis=-1, keepdims=True), 1e-300)
    x = np.clip(1.0 - np.sum(np.asarray(v, float) * h, axis=-1), 0.0, 1.0)
    F = fr.f0 + (fr.f90 - fr.f0) * x ** p
    with np.errstate(divide="ignore", invalid="ignore"):
        cond = np.where(F > 0, p * abs(fr.f90 - fr.f0) * x ** (p - 1) / F, 0.0)
    return 4 * np.finfo(float).eps * cond


def assert_same(got, ref, allowance=0.0):
    got, ref = np.asarray(got), np.asarray(ref)
    allowance = np.broadcast_to(allowance, ref.shape)
    assert got.shape == ref.shape
    assert not np.isnan(got).any()
    assert np.array_equal(np.isinf(got), np.isinf(ref)), "the +inf limits differ"
    zero_mismatch = (got == 0) != (ref == 0)
    assert np.all(np.maximum(np.abs(got), np.abs(ref))[zero_mismatch] < F_ABS), "the zeros differ"
    fin = np.isfinite(ref) & (ref != 0)
    excess = (np.abs(got[fin] - ref[fin]) - F_ABS) / np.abs(ref[fin]) - allowance[fin]
    assert excess.size == 0 or excess.max() <= RTOL, \
        f"max relative difference {excess.max():.3g} beyond the conditioning of F"


def extreme_pairs():
    """Direction pairs at every special case of the formulas."""
    s = np.sqrt(0.5)
    n = [0.0, 0.0, 1.0]
    pairs = [
        (n, n),                                   # normal incidence: h = n, Λ = 0
        ([1, 0, 0], [-1, 0, 0]),                  # l = −v at the horizon: no h
        ([1, 0, 0], [1, 0, 0]),                   # both grazing, same: +inf (h-c) / finite
        ([1, 0, 0], [0, 1, 0]),                   # both grazing, 90° apart
        ([1, 0, 0], n),                           # one grazing
        ([s, 0, s], [-s, 0, s]),                  # mirror pair at 45°
        ([s, 0, s], [s, 0, s]),                   # retro-reflection
        ([0, 0, -1], n),                          # l below the horizon
        ([s, 0, -s], [s, 0, s]),                  # l below, v above
        ([1.0, 0, -0.0], [0.8, 0, 0.6]),          # l on the horizon as −0
        ([1e-9, 0, np.sqrt(1 - 1e-18)], n),       # near normal: s tiny, a huge
    ]
    # Beckmann μΛ at a = μ/s on both sides of its series switch and far into it, for
    # α = 0.05 (s = α sinθ): a = 7.9, 8.0, 8.1, 30.
    for a in (7.9, 8.0, 8.1, 30.0):
        t = 1.0 / (a * 0.05)                       # tanθ = 1/(a α)
        mu = 1.0 / np.sqrt(1 + t * t)
        w = [np.sqrt(1 - mu * mu), 0.0, mu]
        pairs += [(w, n), (w, [-w[0], 0, w[2]])]
    l, v = (np.array([p[i] for p in pairs], dtype=float) for i in (0, 1))
    return l, v


@pytest.mark.parametrize("g2", ["separable", "height_correlated"])
@pytest.mark.parametrize("fresnel, fparams", FRESNEL_CASES,
                         ids=[f"{f}-{'-'.join(f'{k}{v:g}' for k, v in p.items())}" for f, p in FRESNEL_CASES])
@pytest.mark.parametrize("ax, ay", ALPHAS, ids=[f"ax{a:g}-ay{b:g}" for a, b in ALPHAS])
@pytest.mark.parametrize("ndf_name", ["ggx", "beckmann"])   # the others: declined, below
def test_kernel_matches_reference(ndf_name, ax, ay, g2, fresnel, fparams, rng):
    brdf = make_brdf(ndf_name, ax, ay, g2=g2, fresnel=fresnel, kd=0.0, **fparams)
    l = random_upper_directions(rng, 4000)
    v = random_upper_directions(rng, 4000)
    # a quarter of the pairs near the mirror configuration, where the peak of D is
    v[:1000] = l[:1000] * [-1, -1, 1] + rng.normal(0, min(ax, ay), (1000, 3))
    v[:1000] /= np.linalg.norm(v[:1000], axis=1, keepdims=True)
    v[:1000, 2] = np.abs(v[:1000, 2])
    # and some below the horizon, where f = 0
    l[-200:, 2] *= -1
    assert_same(kernel_f(brdf, l, v), reference_f(brdf, l, v), fresnel_condition(brdf, l, v))
    le, ve = extreme_pairs()
    assert_same(kernel_f(brdf, le, ve), reference_f(brdf, le, ve), fresnel_condition(brdf, le, ve))
    assert_same(kernel_f(brdf, ve, le), reference_f(brdf, ve, le), fresnel_condition(brdf, ve, le))


@pytest.mark.parametrize("ndf", ["ggx", "beckmann"])
def test_kernel_with_lambertian_and_broadcasting(ndf, rng):
    """kd/π is added where both directions are upper (and alone where h does not exist);
    shapes broadcast as in the reference: one l against a grid of v."""
    brdf = make_brdf(ndf, 0.2, 0.4, fresnel="schlick", kd=0.3)
    l = np.array([0.5, 0.1, np.sqrt(1 - 0.26)])
    v = random_upper_directions(rng, 600).reshape(20, 30, 3)
    got = kernel_f(brdf, l, v)
    assert got.shape == (20, 30)
    assert_same(got, reference_f(brdf, np.broadcast_to(l, v.shape), v))
    le, ve = extreme_pairs()
    assert_same(kernel_f(brdf, le, ve), reference_f(brdf, le, ve))


def test_parallel_and_serial_loops_agree(rng):
    """Above PARALLEL_MIN pairs the parallel loop runs; it computes the same numbers."""
    brdf = make_brdf("ggx", 0.3, g2="height_correlated", fresnel="schlick")
    n = fast.PARALLEL_MIN + 1000
    l = random_upper_directions(rng, n)
    v = random_upper_directions(rng, n)
    big = kernel_f(brdf, l, v)
    small = np.concatenate([kernel_f(brdf, l[i:i + 1000], v[i:i + 1000]) for i in range(0, n, 1000)])
    np.testing.assert_array_equal(big, small)
    assert_same(big, reference_f(brdf, l, v))


def test_dispatch_uses_the_kernel_only_for_f(rng):
    """BRDF.evaluate(("f",)) goes through the kernel when it covers the model and numba
    is there; a request for more than f, or no numba, keeps the reference path."""
    brdf = make_brdf("ggx", 0.3, fresnel="schlick")
    l = random_upper_directions(rng, 50)
    v = random_upper_directions(rng, 50)
    calls = []
    original = fast.evaluate_f
    try:
        fast.evaluate_f = lambda *a: calls.append(a) or original(*a)
        brdf.evaluate(l, v, ("f",))
        assert len(calls) == (1 if fast.enabled() else 0)
        brdf.evaluate(l, v, ("f", "D"))
        assert len(calls) == (1 if fast.enabled() else 0)
    finally:
        fast.evaluate_f = original
    assert fast.enabled() == (fast.numba is not None and fast.AVAILABLE)


class GGXVariant(GGX):
    """A subclass may change any formula: the kernel must not assume it is GGX."""
    name = "ggx_variant_for_test"


def unsupported_brdfs():
    out = {}
    base = make_brdf("ggx", 0.3)
    for name, form in G2_FORMS.items():
        if name not in ("separable", "height_correlated"):
            out[f"g2={name}"] = dataclasses.replace(base, g2=form)
    for name, cls in FRESNELS.items():
        if name not in ("none", "schlick"):
            out[f"fresnel={name}"] = dataclasses.replace(base, fresnel=cls())
    from app.physics.ndf import NDFS
    for name, cls in NDFS.items():
        if name not in ("ggx", "beckmann"):
            out[f"ndf={name}"] = dataclasses.replace(base, ndf=make_ndf(name, 0.3))
    out["ndf=subclass"] = dataclasses.replace(base, ndf=GGXVariant(0.3))
    out["masking=copy"] = dataclasses.replace(
        base, masking=dataclasses.replace(MASKINGS["smith"], name="smith_copy"))
    return out


UNSUPPORTED = unsupported_brdfs()


@pytest.mark.parametrize("name", sorted(UNSUPPORTED))
def test_declines_what_it_does_not_implement(name, rng):
    """Every other model is declined (spec_args is None) and evaluates exactly as the
    reference does."""
    brdf = UNSUPPORTED[name]
    with _forced():
        assert fast.spec_args(brdf) is None
        l = random_upper_directions(rng, 200)
        v = random_upper_directions(rng, 200)
        got = brdf.evaluate(l, v, ("f",))["f"]
    np.testing.assert_array_equal(got, reference_f(brdf, l, v))


def test_a_new_brdf_field_is_declined():
    """A BRDF with a field the kernel does not know (say, a compensation term) is not
    the model the kernel computes."""
    @dataclasses.dataclass(frozen=True)
    class CompensatedBRDF(BRDF):
        compensation: bool = True

    base = make_brdf("ggx", 0.3)
    brdf = CompensatedBRDF(**{f.name: getattr(base, f.name) for f in dataclasses.fields(base)})
    with _forced():
        assert fast.spec_args(base) is not None
        assert fast.spec_args(brdf) is None


def test_disabled_switches_to_the_reference():
    brdf = make_brdf("ggx", 0.3)
    with fast.disabled():
        assert fast.spec_args(brdf) is None
