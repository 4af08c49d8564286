"""The exponential-power NDF's incomplete-gamma inverse (a per-p guess table and one
Halley step, ndf/exp_power.py) against scipy's gammaincinv/gammainccinv, the routine it
replaces, and by its round trip through scipy's P and Q."""
import numpy as np
import pytest
from scipy.special import gammainc, gammaincc, gammainccinv, gammaincinv

from app.physics.ndf import exp_power as ep

#: relative agreement with scipy where x is a normal float (both lose digits among the
#: subnormals, x < 2.2e-308); measured ≤ 6e-14 (p = 0.25 … 4)
REL = 2e-13
#: |P(a, x)/u − 1| (or Q) of the result; scipy's own inverse leaves ~1.7e-13
ROUND_TRIP = 5e-13
#: x above this is a normal float with margin (the comparison is made there)
X_NORMAL = 1e-290
#: scalar against numpy form: numpy's exp/log differ from math's by an ulp, which the
#: Halley step carries into x at the problem's condition (measured 6e-15)
SCALAR_REL = 1e-13


def _points(rng):
    return np.concatenate([rng.uniform(0.0, 1.0, 4000), 10.0 ** rng.uniform(-300.0, 0.0, 4000),
                           1.0 - 10.0 ** rng.uniform(-16.0, 0.0, 2000), [0.5, 1e-30, 1e-31]])


@pytest.mark.parametrize("p", [0.25, 0.4, 0.6, 1.0, 1.3, 1.7, 2.5, 4.0])
def test_inverse_matches_scipy(p):
    a, q = 1.0 / p, ep._inverse_params(p)
    rng = np.random.default_rng(int(p * 100))
    w = _points(rng)
    # P(a, x) = u
    x, ref = ep._inverse(q, w, 1.0 - w, a), gammaincinv(a, w)
    normal = ref > X_NORMAL
    assert np.max(np.abs(x[normal] / ref[normal] - 1.0)) <= REL
    small = normal & (w <= 0.5)
    assert np.max(np.abs(gammainc(a, x[small]) / w[small] - 1.0)) <= ROUND_TRIP
    # Q(a, x) = v
    x, ref = ep._inverse(q, 1.0 - w, w, a), gammainccinv(a, w)
    normal = (ref > X_NORMAL) & np.isfinite(ref)
    assert np.max(np.abs(x[normal] / ref[normal] - 1.0)) <= REL
    small = normal & (w <= 0.5)
    assert np.max(np.abs(gammaincc(a, x[small]) / w[small] - 1.0)) <= ROUND_TRIP
    # the scalar formula (what the compiled loops run) is the numpy one
    for wi in w[::97]:
        assert ep.inverse_scalar(1.0 - wi, wi, q, 0, a) == pytest.approx(
            float(ep._inverse(q, 1.0 - wi, wi, a)), rel=SCALAR_REL, abs=0.0)


def test_inverse_ends():
    q = ep._inverse_params(1.0)
    assert ep._inverse(q, 0.0, 1.0, 1.0) == 0.0 and ep.inverse_scalar(0.0, 1.0, q, 0, 1.0) == 0.0
    assert ep._inverse(q, 1.0, 0.0, 1.0) == np.inf and ep.inverse_scalar(1.0, 0.0, q, 0, 1.0) == np.inf
    ndf = ep.ExpPower(0.3, p=1.0)     # p = 1: Q(1, x) = e^{−x}, r̃² = −ln v
    v = np.geomspace(1e-300, 1.0, 200)
    assert np.allclose(ndf.radial_ccdf_inv(v), -np.log(v), rtol=1e-14, atol=1e-300)
