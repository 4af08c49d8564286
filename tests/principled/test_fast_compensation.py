"""Kulla-Conty's f_ms from the restricted spline (app/principled/compensation.py) against
the KullaConty lobe of app/integrate (the table's own 2-D spline), per channel."""
from __future__ import annotations

import numpy as np
import pytest

from app.integrate.compensation import kulla_conty
from app.model import make_spec
from app.principled import Principled
from app.principled.compensation import f_ms_rgb, one_minus_E
from app.physics.fresnel import FRESNELS


@pytest.mark.parametrize("roughness", [0.05, 0.3, 0.7, 1.0])
def test_principled_channels_equal_the_integrate_lobes(roughness):
    m = Principled(roughness=roughness, metallic=0.6,
                   options={**Principled().options, "principled_multiscatter": "kulla_conty"})
    channels = m.multiscatter()
    rng = np.random.default_rng(3)
    mu_l, mu_v = rng.random(5000), rng.random(5000)
    mu_l[:4] = [0.0, 1.0, 1e-9, 0.5]
    want = np.stack([ms(mu_l, mu_v) for ms in channels], axis=-1)
    # E's rounding (~1e-16) against 1 − E ~ 1e-4 at α = 0.05², times the lobe's 1/(1 − Ē)
    np.testing.assert_allclose(f_ms_rgb(channels, mu_l, mu_v), want, rtol=1e-9, atol=1e-13)


@pytest.mark.parametrize("model", [dict(alpha=0.5, fresnel="none"), dict(ndf="beckmann", alpha=0.2),
                                   dict(alpha=0.05, f0=0.9)])
def test_one_minus_E_is_the_tables(model):
    term = kulla_conty(make_spec(**model).brdf()).lobes[0]
    mu = np.linspace(0.0, 1.0, 1001)
    np.testing.assert_allclose(one_minus_E(term.table, term.alpha)(mu), 1.0 - term.table.E(mu, term.alpha),
                               rtol=0, atol=1e-13)


def test_a_schlick_basis_table_falls_back_to_its_own_E():
    """Tables of the Schlick basis (table.base set) are not one spline: E itself."""
    class Basis:
        base = object()
        spline = None

        @staticmethod
        def E(mu, alpha):
            return np.full(np.shape(mu), 0.25)
    assert one_minus_E(Basis, 0.3)(np.array([0.5])) == pytest.approx(0.75)
    assert FRESNELS["none"]().F_avg() == 1.0
