"""Monte Carlo albedo: its error bar is honest (coverage), and it converges to quadrature.

Coverage: with 200 seeds (0..199), the fraction of estimates with |E − E_ref| ≤ E_error
must be consistent with 68.3 % and with |E − E_ref| ≤ 2 E_error with 95.4 %: within
3 binomial standard deviations, i.e. 137 ± 20 and 191 ± 9 of 200. E_ref is the
deterministic quadrature of app.integrate.albedo (error ≤ 1e-5, far below E_error).
"""
from __future__ import annotations

import numpy as np
import pytest

from app.integrate.albedo import albedo
from app.integrate.montecarlo import SAMPLERS, albedo_mc
from app.model import make_spec

SEEDS = 200
SAMPLES = 4096


def _within(hits: int, p: float) -> bool:
    sigma = np.sqrt(SEEDS * p * (1.0 - p))
    return abs(hits - SEEDS * p) <= 3.0 * sigma


CASES = [
    ("cosine", {"ndf": "ggx", "alpha": 0.5}, 0.5),
    ("uniform", {"ndf": "ggx", "alpha": 0.5}, 0.8),
    ("ndf", {"ndf": "ggx", "alpha": 0.1}, 0.5),
    ("vndf", {"ndf": "ggx", "alpha": 0.1}, 0.2),
    ("vndf", {"ndf": "beckmann", "alpha": 0.3, "alpha_y": 0.1}, 0.5),
    ("ndf", {"ndf": "beckmann", "alpha": 1.0, "fresnel": "schlick"}, 0.9),
]


@pytest.mark.parametrize("sampler,spec,mu", CASES)
def test_error_bar_coverage(sampler, spec, mu):
    brdf = make_spec(**spec).brdf()
    reference = albedo(brdf, [mu]).E[0]
    runs = [albedo_mc(brdf, mu, 0.0, sampler, SAMPLES, seed) for seed in range(SEEDS)]
    deviation = np.array([abs(r.E[0] - reference) for r in runs])
    error = np.array([r.E_error[0] for r in runs])
    one, two = int(np.sum(deviation <= error)), int(np.sum(deviation <= 2.0 * error))
    assert _within(one, 0.6827), (one, two)
    assert _within(two, 0.9545), (one, two)


@pytest.mark.parametrize("sampler", sorted(SAMPLERS))
def test_estimates_agree_with_quadrature_over_mu(sampler):
    """Vectorised over μ (including grazing μ = 0): every point within 4 standard errors."""
    brdf = make_spec(ndf="ggx", alpha=0.3, kd=0.1).brdf()
    mu = np.array([0.0, 0.05, 0.3, 0.7, 1.0])
    reference = albedo(brdf, mu).E
    result = albedo_mc(brdf, mu, 0.3, sampler, 20_000, 11)
    assert result.E.shape == mu.shape and result.evaluations == mu.size * 20_000
    assert np.all(np.isfinite(result.E)) and np.all(result.E_error > 0)
    assert np.all(np.abs(result.E - reference) <= 4.0 * result.E_error), (result.E, reference)


def test_error_shrinks_like_one_over_root_n():
    brdf = make_spec(ndf="ggx", alpha=0.5).brdf()
    small = albedo_mc(brdf, 0.5, 0.0, "vndf", 2_000, 3).E_error[0]
    large = albedo_mc(brdf, 0.5, 0.0, "vndf", 200_000, 3).E_error[0]
    assert large / small == pytest.approx(0.1, rel=0.15)


def test_two_lobes_use_the_mixture():
    brdf = make_spec(ndf="ggx", alpha=0.5, alpha2=0.05, lobe_mix=0.3).brdf()
    # E is linear in f: the reference is the weighted sum of each lobe's quadrature
    reference = sum(w * albedo(lobe, [0.6]).E[0] for w, lobe in brdf.lobes())
    for sampler in ("ndf", "vndf"):
        r = albedo_mc(brdf, 0.6, 0.0, sampler, 50_000, 5)
        assert abs(r.E[0] - reference) <= 4.0 * r.E_error[0]


def test_bad_arguments_raise_value_error():
    brdf = make_spec(ndf="gtr", alpha=0.3).brdf()
    with pytest.raises(ValueError, match="no vndf sampler for ndf=gtr"):
        albedo_mc(brdf, 0.5, 0.0, "vndf", 100, 0)
    with pytest.raises(ValueError, match="sampler="):
        albedo_mc(brdf, 0.5, 0.0, "importance", 100, 0)
