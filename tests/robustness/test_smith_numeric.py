"""masking=smith_numeric reads the general Smith integral from a table: its stated error
(TABLE_G1_ERROR in G1) holds against the direct quadrature for every NDF at the ends of
its parameter ranges, anisotropic stretch included."""
from __future__ import annotations

import numpy as np
import pytest

from app.physics.masking import G1
from app.physics.ndf import NDFS
from tests.shape_extremes import shape_extremes
from app.physics.smith_integral import mu_Lambda_quadrature
from app.physics.smith_table import mu_Lambda_smith_numeric as mu_Lambda_numeric
from app.physics.smith_table import TABLE_G1_ERROR, lambda_table


def _cases():
    for name, cls in sorted(NDFS.items()):
        for shape in shape_extremes(cls):
            for alphas in [(1e-4, None), (0.3, None), (1.0, None)] + (
                    [(0.05, 0.9)] if cls.shape_invariant else []):
                yield name, shape, alphas


CASES = list(_cases())


def _directions(rng, n):
    """Directions over the closed upper hemisphere, with the pole, grazing and near-grazing."""
    cos_t = np.concatenate([rng.uniform(0.0, 1.0, n), [0.0, 1.0, 1e-6, 1e-3, 0.9999]])
    phi = rng.uniform(0.0, 2 * np.pi, cos_t.size)
    sin_t = np.sqrt(1.0 - cos_t ** 2)
    return np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=-1)


@pytest.mark.parametrize("name, shape, alphas", CASES, ids=[f"{n}{s}{a}" for n, s, a in CASES])
def test_table_within_its_stated_error_of_the_direct_integral(name, shape, alphas):
    ndf = NDFS[name](*alphas, **shape)
    w = _directions(np.random.default_rng(7), 300)
    mu = w[:, 2]
    direct = G1(mu, mu_Lambda_quadrature(ndf, w))
    table = G1(mu, mu_Lambda_numeric(ndf, w))
    assert np.all(np.isfinite(table))
    assert np.max(np.abs(table - direct)) <= TABLE_G1_ERROR


def test_below_the_horizon_and_at_the_pole_no_masking():
    ndf = NDFS["ggx"](0.3)
    w = np.array([[0.0, 0.0, 1.0], [0.6, 0.0, -0.8]])
    assert mu_Lambda_numeric(ndf, w).tolist() == [0.0, 0.0]


def test_one_table_per_shape_whatever_alpha_of_a_shape_invariant_ndf():
    """The table of GGX at α = 0.1 is the one at α = 0.7 (the stretch carries α); GTR,
    not shape-invariant, has one per α."""
    assert lambda_table(NDFS["ggx"](0.1)) is lambda_table(NDFS["ggx"](0.7, 0.2))
    assert lambda_table(NDFS["gtr"](0.1)) is not lambda_table(NDFS["gtr"](0.7))


@pytest.mark.parametrize("name, shape, alphas", [c for c in CASES if c[2][1] is None],
                         ids=[f"{n}{s}{a}" for n, s, a in CASES if a[1] is None])
def test_interpolant_is_positive_and_non_increasing(name, shape, alphas):
    """h(a) = μΛ/s falls with a (dh/da = −(1/π)∫ atan(q/a) du ≤ 0): between the nodes too,
    where a cubic through the steep exponential tails could dip below 0."""
    table = lambda_table(NDFS[name](*alphas, **shape))
    h = table.h(np.exp(np.linspace(np.log(table.a_min), np.log(table.a_max), 400_003)))
    assert np.all(h >= 0.0)
    assert np.all(np.diff(h) <= 1e-15 * np.maximum(h[:-1], 1e-300))
