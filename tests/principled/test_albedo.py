"""Each lobe's albedo (app/principled/albedo.py) against a brute midpoint rule over the
hemisphere of l of the lobe's f (checked against disney.brdf in test_lobes.py)."""
from __future__ import annotations

import numpy as np
import pytest

from app.principled import LOBES, Principled
from app.principled.albedo import lobe_albedo

from .references import DEFAULTS


def _midpoint(m, lobe, theta_v, n=700):
    mu = (np.arange(n) + 0.5) / n
    phi = -np.pi + 2 * np.pi * (np.arange(2 * n) + 0.5) / (2 * n)
    s = np.sqrt(1 - mu * mu)
    l = np.stack(np.broadcast_arrays(s[:, None] * np.cos(phi), s[:, None] * np.sin(phi), mu[:, None]), axis=-1)
    v = np.array([np.sin(theta_v), 0.0, np.cos(theta_v)])
    f = m.f_rgb(l.reshape(-1, 3), v[None, :], lobe).reshape(n, 2 * n, 3)
    return np.sum(f * mu[:, None, None], axis=(0, 1)) * (1.0 / n) * (np.pi / n)


@pytest.mark.parametrize("lobe", LOBES)
def test_lobe_albedo_against_midpoint(lobe):
    p = {**DEFAULTS, "roughness": 0.6, "sheen": 0.7, "clearcoat": 1.0, "clearcoat_gloss": 0.0,
         "subsurface": 0.4, "metallic": 0.2, "anisotropic": 0.5}
    m = Principled(**p)
    thetas = np.deg2rad([10.0, 50.0, 75.0])
    E, err = lobe_albedo(m, np.cos(thetas))[lobe]
    want = np.array([_midpoint(m, lobe, t) for t in thetas])
    # the midpoint rule's error is ~1e-5 here (kinks and the peak are resolved by n = 700)
    np.testing.assert_allclose(E, want, atol=err + 3e-4, rtol=2e-3)
