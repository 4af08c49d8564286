"""Sines and cosines of degrees inside the compiled loops (app/kernels/angles.py) against
mpmath at 50 digits: within 2 ulp of the value (sin, cos ≥ 1e-300 apart from exact zeros),
exact 0 and ±1 at multiples of 90° (never -0.0), for angles from -10^6 to 10^6 degrees,
near the reduction's ties (±45°, ±135°) and with a correction e (the isotropic turn's
rounding error of φ_l − φ_v); and the turned directions against the unturned ones."""
from __future__ import annotations

import math

import mpmath
import numpy as np
import pytest

from app import kernels

pytestmark = pytest.mark.skipif(not kernels.ENABLED, reason="numba absent or BRDF_FAST=0")

numba = pytest.importorskip("numba")
angles = pytest.importorskip("app.kernels.angles")

ULP = np.finfo(float).eps


@numba.njit
def _sincos(a, e):
    s, c = np.empty(a.size), np.empty(a.size)
    for i in range(a.size):
        s[i], c[i] = angles.sincos_deg(a[i], e[i])
    return s, c


def _reference(a: float, e: float) -> tuple[float, float]:
    with mpmath.workdps(50):
        x = (mpmath.mpf(a) + mpmath.mpf(e)) * mpmath.pi / 180
        return float(mpmath.sin(x)), float(mpmath.cos(x))


def _assert_within_ulps(got, want, ulps=2.0):
    scale = np.maximum(np.abs(want), 1e-300)
    err = np.abs(got - want) / (scale * ULP)
    assert np.all(err <= ulps), f"{err.max():.2f} ulp at {np.argmax(err)}"


def test_sin_cos_of_degrees_match_mpmath():
    rng = np.random.default_rng(11)
    a = np.concatenate([rng.uniform(-360, 360, 2000), rng.uniform(-1e6, 1e6, 500),
                        np.array([45.0, -45.0, 135.0, -135.0, 44.999999999, 45.000000001, 1e-300,
                                  -1e-12, 179.99999999, -180.0 + 1e-9, 89.9999999999])])
    e = np.where(np.arange(a.size) % 3 == 0, np.spacing(np.abs(a)) * 0.37, -0.0)
    s, c = _sincos(a, e)
    ref = np.array([_reference(x, y) for x, y in zip(a, e)])
    exact_zero = ref == 0.0
    _assert_within_ulps(s[~exact_zero[:, 0]], ref[~exact_zero[:, 0], 0])
    _assert_within_ulps(c[~exact_zero[:, 1]], ref[~exact_zero[:, 1], 1])


def test_multiples_of_90_are_exact_and_never_negative_zero():
    k = np.arange(-16, 17, dtype=float)
    a = np.concatenate([90.0 * k, 90.0 * k + 360.0 * 1e4])
    s, c = _sincos(a, np.full(a.size, -0.0))
    quarter = np.round(a / 90.0).astype(int) % 4
    assert np.array_equal(s, np.array([0.0, 1.0, 0.0, -1.0])[quarter])
    assert np.array_equal(c, np.array([1.0, 0.0, -1.0, 0.0])[quarter])
    assert not np.any(np.signbit(s[s == 0.0])) and not np.any(np.signbit(c[c == 0.0]))


def test_turned_directions_keep_the_angles_between_them():
    """directions_deg_isotropic turns l and v by -φ_v: l·v, the heights and the azimuth
    between them are those of directions_deg's unturned pair (to rounding), v at φ = 0."""
    rng = np.random.default_rng(12)
    n = angles.BLOCK
    th_l, th_v = rng.uniform(0, 90, n), rng.uniform(0, 90, n)
    ph_l, ph_v = rng.uniform(-720, 720, n), rng.uniform(-720, 720, n)
    plain, turned = np.empty((6, n)), np.empty((6, n))
    angles.directions_deg(th_l, ph_l, th_v, ph_v, plain, np.uint64(0), np.uint64(n))
    angles.directions_deg_isotropic(th_l, ph_l, th_v, ph_v, turned, np.uint64(0), np.uint64(n))
    assert np.all(turned[4] == 0.0) and np.all(turned[3] >= 0.0)
    np.testing.assert_allclose(turned[[2, 5]], plain[[2, 5]], rtol=0, atol=4 * ULP)
    dot = lambda w: w[0] * w[3] + w[1] * w[4] + w[2] * w[5]             # noqa: E731
    cross = lambda w: w[0] * w[4] - w[1] * w[3]                          # noqa: E731
    np.testing.assert_allclose(dot(turned), dot(plain), rtol=0, atol=8 * ULP)
    np.testing.assert_allclose(cross(turned), cross(plain), rtol=0, atol=8 * ULP)
    # and against the definition: the azimuth between them is φ_l − φ_v
    want = np.sin(np.radians(th_l)) * np.sin(np.radians(th_v)) * np.sin(np.radians(ph_l - ph_v))
    np.testing.assert_allclose(-cross(turned), want, rtol=0, atol=1e-13)
    assert math.isfinite(float(dot(turned).sum()))
