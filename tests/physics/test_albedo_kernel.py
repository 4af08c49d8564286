"""The compiled albedo integrand (app/integrate/albedo_kernel.py) against the numpy one.

Both evaluate the same integrand at the same nodes (albedo._integrate_order lays them);
they must agree to rounding: 1e-12 absolute on E ∈ [0, 1] (sums of ~10⁴ terms each
good to ~1e-15 relative), for every model the kernel covers, at grazing, normal and
oblique views, isotropic and anisotropic, at the orders the adaptive rule uses.
Accuracy of the quadrature itself is tested in test_albedo.py against brute force.
"""
from __future__ import annotations

import numpy as np
import pytest

from app.integrate import albedo as albedo_mod
from app.integrate import albedo_kernel
from app.physics import fast

from .conftest import make_brdf
from .test_fast_path import _forced

ATOL = 1e-12
MU = np.array([0.0, 1e-3, 0.02, 0.3, 0.77, 1.0])
CASES = [  # (ndf, α_x, α_y, g2, fresnel, fresnel params, φ_v)
    ("ggx", 0.3, 0.3, "height_correlated", "schlick", {}, 0.0),
    ("ggx", 1e-3, 1e-3, "height_correlated", "none", {}, 0.0),
    ("ggx", 1.0, 1.0, "separable", "schlick", {"f0": 0.9, "f90": 0.1}, 0.0),
    ("ggx", 0.05, 0.5, "height_correlated", "none", {}, 0.7),
    ("beckmann", 0.3, 0.3, "separable", "schlick", {}, 0.0),
    ("beckmann", 0.01, 0.01, "height_correlated", "none", {}, 0.0),
    ("beckmann", 1.0, 0.1, "height_correlated", "schlick", {}, 2.0),
]


def views(phi):
    s = np.sqrt(1.0 - MU * MU)
    return np.stack([s * np.cos(phi), s * np.sin(phi), MU], axis=-1)


@pytest.mark.parametrize("order", [8, 24, 96])
@pytest.mark.parametrize("ndf, ax, ay, g2, fresnel, fparams, phi", CASES,
                         ids=[f"{c[0]}-{c[1]:g}-{c[2]:g}-{c[3][:3]}-{c[4]}" for c in CASES])
def test_kernel_integrand_matches_numpy(ndf, ax, ay, g2, fresnel, fparams, phi, order):
    brdf = make_brdf(ndf, ax, ay, g2=g2, fresnel=fresnel, kd=0.2, **fparams)
    v = views(phi)
    with _forced():
        assert albedo_kernel.spec_args(brdf) is not None
        got = albedo_mod._integrate_order(brdf, v, order)
    with fast.disabled():
        assert albedo_kernel.spec_args(brdf) is None
        ref = albedo_mod._integrate_order(brdf, v, order)
    assert np.all(np.isfinite(got))
    np.testing.assert_allclose(got, ref, rtol=0, atol=ATOL)


def test_kernel_declines_phi_dependent_forms():
    """A G2 form that needs the azimuth difference is not in the kernel."""
    from app.physics.g2 import G2_FORMS
    import dataclasses
    for form in G2_FORMS.values():
        if form.needs_phi:
            brdf = dataclasses.replace(make_brdf("ggx", 0.3), g2=form)
            with _forced():
                assert albedo_kernel.spec_args(brdf) is None
