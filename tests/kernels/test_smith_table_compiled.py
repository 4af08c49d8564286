"""The Smith table's integrals by the compiled loop (kernel.smith_h) against the direct
numpy Smith integral (physics/smith_integral.h_derivatives, the independent reference the
table was built from), and the table built on them against the direct integral's G1."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from app import kernels
from app.physics import smith_integral, smith_table
from app.physics.ndf import NDFS

from .test_compiled_matches_numpy import CASES as DESIGN, _brdf

pytestmark = pytest.mark.skipif(not kernels.ENABLED, reason="numba absent or BRDF_FAST=0")

#: compiled against numpy, relative in h and absolute in dh/da (|dh/da| ≤ ½): the sums run
#: in another order and the radial inverses' math differs from numpy's by ulps, which
#: GTR's inverse at α = 1e-3 amplifies (measured ≤ 4e-14 in h, 7e-13 in the slope there,
#: 2e-15 elsewhere)
#: (Below α = 1e-3 GTR's radial inverse is ill-conditioned: at α = 1e-4 the two sums
#: differ by up to 2e-8 relative, and both tables are equally far from the direct
#: integral in G1, which the second test checks there.)
H_REL = 1e-12
SLOPE_ABS = 2e-12
#: the curvature d²h/da² = (1/π)∫ du/q, relative: its first terms (q → 0) carry the
#: radial inverses' ulps at the condition 1/q² (measured ≤ 5.3e-5 for GTR γ = 2, α = 0.3
#: at a ≈ 7e3, where h'' ~ 1e-12; ≤ 3e-8 elsewhere). The table's quintic uses it times
#: Δx² a², which makes that ≤ 1e-12 in h.
CURVATURE_REL = 1e-4

CASES = [("gtr", 0.3, {"gamma": 2.0}), ("gtr", 1e-3, {"gamma": 1.6}), ("gtr", 1.0, {"gamma": 6.0}),
         ("blinn_phong", 0.05, {}), ("blinn_phong", 0.9, {}),
         ("exp_power", 0.3, {"p": 0.25}), ("exp_power", 0.3, {"p": 4.0}),
         ("student_t", 0.3, {"gamma": 2.7}), ("beckmann", 0.3, {}), ("ggx", 0.3, {})]


def _kernel(name, alpha, shape):
    """The NDF and the loops of test_compiled_matches_numpy's case of this NDF with the
    numeric masking (smith_h depends on the NDF alone: no loops compiled for this file)."""
    ndf = NDFS[name](alpha, None, **shape)
    case = next(c for c in DESIGN if c[:2] == (name, "smith_numeric"))
    lobe = replace(_brdf(case), ndf=ndf)
    kernel = kernels.compile_now(lobe, "albedo")     # smith_h and the albedo's rows
    assert kernel is not None
    return ndf, kernel


@pytest.mark.parametrize("name,alpha,shape", CASES, ids=lambda c: str(c))
def test_compiled_smith_integrals_match_numpy(name, alpha, shape):
    ndf, kernel = _kernel(name, alpha, shape)
    x = np.linspace(np.log(smith_table.A_MIN), np.log(smith_table.A_MAX), 301)
    a = np.concatenate([np.exp(x), [0.0, 0.37, 1.0, 3.0]])
    h, slope, curvature = kernel.smith_h(ndf, a)
    h_ref, slope_ref, curvature_ref = smith_integral.h_derivatives(ndf, a)
    assert np.all(np.abs(h - h_ref) <= H_REL * np.abs(h_ref))
    assert np.max(np.abs(slope - slope_ref)) <= SLOPE_ABS
    assert np.all(np.abs(curvature - curvature_ref) <= CURVATURE_REL * np.abs(curvature_ref))


@pytest.mark.parametrize("name,alpha,shape", [CASES[0], CASES[1], CASES[3], CASES[5],
                                              ("gtr", 1e-4, {"gamma": 2.0})], ids=str)
def test_table_from_compiled_integrals_meets_its_bound(name, alpha, shape):
    ndf, _ = _kernel(name, alpha, shape)
    assert type(ndf) in smith_table.COMPILED_H
    smith_table._table.cache_clear()
    table = smith_table.lambda_table(ndf)        # built by the compiled loop
    theta = np.radians(np.concatenate([np.linspace(1.0, 89.0, 60), 90.0 - np.geomspace(1e-4, 1.0, 20)]))
    w = np.stack([np.sin(theta), np.zeros_like(theta), np.cos(theta)], axis=-1)
    mu = w[:, 2]
    s = ndf.stretched_sin(w)
    g1_table = mu / (mu + table.mu_Lambda(mu, s))
    g1_direct = mu / (mu + smith_integral.mu_Lambda_quadrature(ndf, w))
    assert np.max(np.abs(g1_table - g1_direct)) <= smith_table.TABLE_G1_ERROR
