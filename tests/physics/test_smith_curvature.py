"""The Smith integral's derivatives (smith_integral.h_derivatives), which the Λ table's
quintic interpolant rests on, against closed forms and finite differences, and the quintic
Hermite itself (smith_table.quintic_hermite, node_values) against the direct integral at
every table node."""
from __future__ import annotations

import numpy as np
import pytest

from app import kernels
from app.physics import smith_integral, smith_table
from app.physics.ndf import NDFS
from tests.shape_extremes import shape_extremes

A = np.concatenate([np.geomspace(1e-5, 1e3, 60), [0.37, 1.0, 3.0]])


def _ggx(a):
    """h = aΛ, dh/da = −∫_a^∞ g, d²h/da² = g(a) = 1/(2(1 + a²)^{3/2}) (GGX's marginal
    slope density; Heitz 2014, eq. 72 and Table 1 for Λ)."""
    root = np.sqrt(1.0 + a * a)      # √(1 + a²) − a = 1/(√(1 + a²) + a), no cancellation
    return 0.5 / (root + a), -0.5 / (root * (root + a)), 0.5 / root ** 3


def _beckmann(a):
    """g(a) = e^{−a²}/√π; h = e^{−a²}/(2√π) − a erfc(a)/2 (Heitz 2014, Table 1), which
    cancels for a ≫ 1 (compared at a ≤ 3)."""
    from scipy.special import erfc
    g = np.exp(-a * a) / np.sqrt(np.pi)
    return 0.5 * g - 0.5 * a * erfc(a), -0.5 * erfc(a), g


@pytest.mark.parametrize("name, closed", [("ggx", _ggx), ("beckmann", _beckmann)])
def test_derivatives_match_the_closed_forms(name, closed):
    h, slope, curvature = smith_integral.h_derivatives(NDFS[name](1.0), A)
    h_ref, slope_ref, curvature_ref = closed(A)
    keep = A <= 3.0
    # h and dh/da to the rule's accuracy (measured ≤ 1e-10 and 1.2e-9 relative, GGX)
    assert np.allclose(h[keep], h_ref[keep], rtol=1e-8, atol=0.0)
    assert np.allclose(slope[keep], slope_ref[keep], rtol=1e-8, atol=0.0)
    assert np.allclose(curvature[keep], curvature_ref[keep], rtol=1e-9, atol=0.0)


@pytest.mark.parametrize("name, alpha, shape", [
    ("gtr", 0.3, {"gamma": 2.0}), ("gtr", 0.05, {"gamma": 10.0}), ("blinn_phong", 0.2, {}),
    ("exp_power", 1.0, {"p": 0.25}), ("exp_power", 1.0, {"p": 4.0}),
    ("student_t", 1.0, {"gamma": 2.7})])
def test_curvature_is_the_slopes_derivative(name, alpha, shape):
    """d²h/da² against a central difference of the slope integral (step 1e-4 a: the
    slope's own quadrature error, ~1e-10, divided by the step leaves ~2e-6 relative at
    exponential power p = 0.25; compared where h ≥ 1e-6, before the steep exponential
    tails the difference does not resolve), and against the same integral at 4× the
    order (measured ≤ 3e-7 relative, GTR γ = 10; ≤ 1e-8 elsewhere)."""
    ndf = NDFS[name](alpha, None, **shape)
    a = np.geomspace(1e-3, 10.0, 25)
    step = 1e-4 * a
    h, _, curvature = smith_integral.h_derivatives(ndf, a)
    difference = (smith_integral.h_derivatives(ndf, a + step)[1]
                  - smith_integral.h_derivatives(ndf, a - step)[1]) / (2.0 * step)
    smooth = h >= 1e-6
    assert np.allclose(curvature[smooth], difference[smooth], rtol=1e-5, atol=0.0)
    live = curvature > 1e-200
    finer = smith_integral.h_derivatives(ndf, a, 4 * smith_integral.ORDER)[2]
    assert np.allclose(curvature[live], finer[live], rtol=1e-6, atol=0.0)


def test_quintic_hermite_is_exact_for_quintics():
    p = np.polynomial.Polynomial([0.3, -1.0, 2.0, 0.5, -0.25, 0.125])
    x0, x1 = -0.4, 0.7
    d1, d2 = p.deriv(), p.deriv(2)
    x = np.linspace(x0, x1, 37)
    value, slope = smith_table.quintic_hermite(x0, x1, p(x0), d1(x0), d2(x0), p(x1), d1(x1), d2(x1), x)
    assert np.allclose(value, p(x), rtol=0.0, atol=1e-14)
    assert np.allclose(slope, d1(x), rtol=0.0, atol=1e-13)


def _cases():
    for name, cls in sorted(NDFS.items()):
        for shape in shape_extremes(cls):
            for alpha in ([1.0] if cls.shape_invariant else [1e-4, 1e-3, 0.3, 1.0]):
                yield name, shape, alpha


CASES = list(_cases())


@pytest.mark.parametrize("name, shape, alpha", CASES, ids=[f"{n}{s}{a}" for n, s, a in CASES])
def test_node_values_within_their_share_of_the_table_error(name, shape, alpha):
    """Every node of the table (2049: most interpolated by the quintic) against the direct
    integral there, in G1 (Λ = h/a, ΔG1 = Δh a/(a + h)²), on the numpy path: within
    QUINTIC_G1_ERROR, except where the reference rule itself is noisy between neighbouring
    nodes (GTR at α ≤ 1e-3, whose radial inverse is ill-conditioned, and Student-t at
    γ → 1.5, where Λ diverges: its order-192 values are 1e-8 to 2e-7 from order 768's)."""
    ndf = NDFS[name](alpha, None, **shape)
    x = np.linspace(np.log(smith_table.A_MIN), np.log(smith_table.A_MAX), smith_table.TABLE_NODES)
    a = np.exp(x)
    # the numpy path even where another test of this process compiled the NDF's loops
    # (test_smith_table_compiled.py holds those to their own bounds)
    with kernels.disabled():
        values, slopes, h0 = smith_table.node_values(ndf, x)
    h, dh_da, _ = smith_integral.h_derivatives(ndf, a)
    live = h >= smith_table.H_FLUSH
    miss = np.abs(values - h)[live] * a[live] / (a[live] + h[live]) ** 2
    noisy = (name == "gtr" and alpha <= 1e-3) or (name == "student_t" and shape["gamma"] < 1.6)
    assert np.max(miss) <= (smith_table.TABLE_G1_ERROR / 2 if noisy else smith_table.QUINTIC_G1_ERROR)
    # the grazing value, integrated directly (numpy or the compiled loop: the same to an ulp)
    assert h0 == pytest.approx(smith_integral.h_derivatives(ndf, np.zeros(1))[0][0], rel=1e-14)
    # the slopes feed the table's cubic Hermite, whose slope basis functions reach
    # (4/27) Δx: a slope off by δ moves h by ≤ (4/27) Δx δ between the nodes
    shift = 4.0 / 27.0 * (x[1] - x[0]) * np.abs(slopes - a * dh_da)[live]
    assert np.max(shift * a[live] / (a[live] + h[live]) ** 2) <= (
        smith_table.TABLE_G1_ERROR / 2 if noisy else smith_table.QUINTIC_G1_ERROR)
