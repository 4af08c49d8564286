"""sin and cos of an angle in degrees as the compiled degrees loops compute them
(compose.sincos_deg), against references that do not use it: mpmath at 50 digits
(sin(a π/180) of the double a exactly), numpy's own sin/cos over the API's angles
(θ in [0, 90]°, φ in [−360, 360]°, and the lobe's φ + 180°), and the closed forms at
multiples of 90° (exactly 0 and ±1, zeros +0.0: numpy's radians path gives cos 90° =
6.1e-17, sin 180° = 1.2e-16).

Called through a loop compiled here with the degrees loops' flags (fastmath "contract",
so the same fused multiply-adds)."""
from __future__ import annotations

import mpmath
import numba
import numpy as np
import pytest

from app import kernels
from app.kernels import compose
from app.model import make_spec

pytestmark = pytest.mark.skipif(not kernels.ENABLED, reason="numba absent or BRDF_FAST=0")

#: ulp of 1.0: sin and cos are ≤ 1 in magnitude, so an absolute error of k·EPS is ≤ k ulp
#: of any result ≥ 0.5 and of the largest ulp of numpy's own argument rounding
EPS = np.finfo(float).eps
#: mpmath's working precision (decimal digits) for the reference
DIGITS = 50
#: the largest error allowed against mpmath, in ulp of the true value: the reduction to
#: [−45°, 45°] is exact, the polynomials are fitted to 1.2e-16, and x = r·π/180 (π/180 itself
#: rounded), the polynomials and the result each round once; measured over 40 000 random
#: angles in [0, 90] and [−360, 360]: largest 1.51 ulp, mean 0.30 (numpy's radians path
#: 1.45 against the same reference)
MAX_ULP = 2.0


@pytest.fixture(scope="module")
def sincos():
    brdf = make_spec(ndf="ggx", alpha=0.3, fresnel="schlick").brdf()    # the default's loops
    assert kernels.compile_now(brdf) is not None
    fn = compose.load(kernels.components(brdf)).sincos_deg

    @numba.njit(fastmath={"contract"}, error_model="numpy")
    def run(a, lo, s, c):
        for k in range(a.size):
            s[k], c[k] = fn(a[k], lo[k])

    def call(a, lo=None):
        a = np.ascontiguousarray(a, dtype=float)
        lo = np.zeros_like(a) if lo is None else np.ascontiguousarray(lo, dtype=float)
        s, c = np.empty_like(a), np.empty_like(a)
        run(a, lo, s, c)
        return s, c
    return call


def _ulp(x):
    return np.spacing(np.abs(x))


def test_against_mpmath_within_two_ulp(sincos):
    rng = np.random.default_rng(37)
    a = np.concatenate([rng.uniform(0.0, 90.0, 1500), rng.uniform(-360.0, 360.0, 1500),
                        rng.uniform(-540.0, 540.0, 500), 10.0 ** rng.uniform(-12, 13, 500),
                        [1e-300, 5e-324, 44.999999999999, 45.0, 45.000000000001, 89.99999999999,
                         2.0 ** 46 - 1.0, -(2.0 ** 46)]])
    s, c = sincos(a)
    mpmath.mp.dps = DIGITS
    for x, sx, cx in zip(a, s, c):
        t = mpmath.mpf(float(x)) * mpmath.pi / 180
        for got, want in ((sx, float(mpmath.sin(t))), (cx, float(mpmath.cos(t)))):
            scale = max(_ulp(want), 5e-324)
            assert abs(got - want) <= MAX_ULP * scale, (x, got, want, abs(got - want) / scale)


def test_against_numpy_over_the_api_angles(sincos):
    """numpy's sin(radians(a)) rounds a·π/180 first (π/180 and the product): its own error
    is up to |a|·π/180·EPS absolute; the two agree within that plus two EPS."""
    rng = np.random.default_rng(7)
    a = np.concatenate([np.linspace(0.0, 90.0, 90_001), np.linspace(-360.0, 360.0, 720_001),
                        rng.uniform(-540.0, 540.0, 200_000)])
    s, c = sincos(a)
    r = np.radians(a)
    allowed = (np.abs(r) + 2.0) * EPS
    assert np.all(np.abs(s - np.sin(r)) <= allowed)
    assert np.all(np.abs(c - np.cos(r)) <= allowed)


def test_exact_at_multiples_of_90_degrees(sincos):
    k = np.concatenate([np.arange(-16, 17), [4001, -4002, 2 ** 30, -(2 ** 38) + 1]]).astype(float)
    s, c = sincos(90.0 * k)
    m = np.mod(k, 4)
    np.testing.assert_array_equal(s, np.select([m == 1, m == 3], [1.0, -1.0], 0.0))
    np.testing.assert_array_equal(c, np.select([m == 0, m == 2], [1.0, -1.0], 0.0))
    zeros = np.concatenate([s[s == 0], c[c == 0]])
    assert zeros.size and not np.any(np.signbit(zeros)), "zeros are +0.0 (no −0.0 height)"
    s, c = sincos(np.array([-0.0]))
    assert s[0] == 0.0 and not np.signbit(s[0]) and c[0] == 1.0
    # numpy's radians path is not exact there; the loops' directions are
    assert np.cos(np.radians(90.0)) != 0.0 and np.sin(np.radians(180.0)) != 0.0


def test_a_rounding_error_carried_as_lo(sincos):
    """sin(a + lo) with lo below a's ulp: φ_v − φ_l as hi + lo (compose.two_diff)."""
    phi_v, phi_l = np.array([300.1, 0.1, 359.7, 12.3]), np.array([0.3, 359.9, 0.3, 12.3])
    hi = phi_v - phi_l
    lo = (phi_v - (hi - (hi - phi_v))) - (phi_l + (hi - phi_v))      # TwoSum, written out
    s, c = sincos(hi, lo)
    mpmath.mp.dps = DIGITS
    for x, y, sx, cx in zip(phi_v, phi_l, s, c):
        t = (mpmath.mpf(float(x)) - mpmath.mpf(float(y))) * mpmath.pi / 180
        assert abs(sx - float(mpmath.sin(t))) <= MAX_ULP * max(_ulp(float(mpmath.sin(t))), 5e-324)
        assert abs(cx - float(mpmath.cos(t))) <= MAX_ULP * _ulp(float(mpmath.cos(t)))


def test_outside_the_exact_range_nan(sincos):
    s, c = sincos(np.array([2.0 ** 46 * 1.5, -1e300, np.inf, -np.inf, np.nan]))
    assert np.all(np.isnan(s)) and np.all(np.isnan(c))
    assert compose.TEMPLATE.count("ANGLE_MAX = 70368744177664.0") == 1 and 2.0 ** 46 == 70368744177664.0
