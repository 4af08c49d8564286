"""The trade-off of albedo methods (app/analysis/tradeoff.py): the reference against an
independent brute force, the quadrature converging, Monte Carlo errors within their
standard errors, the points ordered by cost, and the time budget honoured."""
from __future__ import annotations

import time

import numpy as np
import pytest

from app.integrate import budget
from app.analysis import tradeoff as to
from app.model import make_spec
from tests.reference import albedo_brute_force

GGX = {0.1: {"ndf": "ggx", "alpha": 0.1}, 0.5: {"ndf": "ggx", "alpha": 0.5}}


def _key(values: dict):
    return tuple(sorted(make_spec(**values).values.items()))


@pytest.fixture(scope="module")
def runs():
    """One default trade-off per GGX roughness (Schlick F₀ = 0.04, the default model)."""
    out = {}
    for alpha, values in GGX.items():
        out[alpha] = to.tradeoff(make_spec(**values).brdf(), _key(values))
    return out


def _points(data: dict, method: str):
    rows = [i for i, m in enumerate(data["method"]) if m == method]
    return {k: np.asarray(data[k])[rows] for k in
            ("budget", "evaluations", "seconds", "error", "error_rms", "E_error", "within_reported")}


@pytest.mark.parametrize("mu", [0.0, 0.25, 0.5, 1.0])
def test_reference_agrees_with_brute_force(mu):
    """E_ref (refined quadrature in slope space) against tests/reference's adaptive
    cubature of f(l, v) μ_l over (μ_l, φ_l), which shares no code with it: within the two
    error estimates (the cubature's ~4e-8 at tol 1e-6; 1e-7 took 3 s a point)."""
    values = GGX[0.5]
    brdf = make_spec(**values).brdf()
    ref, _ = to.reference(brdf, _key(values), [mu])
    brute, brute_err, _ = albedo_brute_force(brdf, mu, 0.0, tol=1e-6)
    assert abs(ref["E"][0] - brute) <= ref["E_error"][0] + brute_err + 1e-12
    assert ref["error"] <= 1e-8                      # the reference reaches its target here


@pytest.mark.parametrize("alpha", sorted(GGX))
def test_quadrature_error_falls_with_the_order(runs, alpha):
    q = _points(runs[alpha], "quadrature")
    assert list(q["budget"]) == list(to.QUADRATURE_ORDERS)
    resolved = q["error"] > 10 * runs[alpha]["reference_error"]   # above the reference's bound
    err = q["error"][resolved]
    assert err.size >= 2 and np.all(np.diff(err) < 0), q["error"]
    assert q["error"][-1] < 1e-6
    # the reported error is a bound: never below what is measured (plus the reference's)
    assert np.all(q["error"] <= q["E_error"] + runs[alpha]["reference_error"])
    assert np.all(q["within_reported"] == 1.0)


# Monte Carlo: at every μ, |E − E_ref| ≤ K·σ̂ (σ̂ the reported standard error) for
# N ≥ 1024 samples, where the estimator is close to Gaussian. Per μ a Gaussian exceeds
# 4.5σ with probability 6.8e-6; over 2 models × 4 samplers × 3 budgets × 9 μ = 216
# comparisons the chance that a correct estimator fails somewhere is ≤ 1.5e-3 (union
# bound, whatever the correlation between μ). The point's error is the max over μ and
# its E_error the max of σ̂ over μ, so error ≤ K·E_error follows from the per-μ bound.
K_SIGMA = 4.5
MC_MIN_SAMPLES = 1024


@pytest.mark.parametrize("alpha", sorted(GGX))
@pytest.mark.parametrize("method", ["mc_uniform", "mc_cosine", "mc_ndf", "mc_vndf"])
def test_monte_carlo_error_within_its_standard_errors(runs, alpha, method):
    p = _points(runs[alpha], method)
    big = p["budget"] >= MC_MIN_SAMPLES
    assert big.sum() == 3
    ref_err = runs[alpha]["reference_error"]
    assert np.all(p["error"][big] <= K_SIGMA * p["E_error"][big] + ref_err), p
    assert np.all(p["error_rms"] <= p["error"])


@pytest.mark.parametrize("alpha", sorted(GGX))
def test_points_are_monotone_in_evaluations(runs, alpha):
    data = runs[alpha]
    n_mu = data["mu_count"]
    for method in data["methods"]:
        p = _points(data, method)
        assert np.all(np.diff(p["budget"]) > 0) and np.all(np.diff(p["evaluations"]) > 0)
        if method.startswith("mc_"):
            assert np.array_equal(p["evaluations"], p["budget"] * n_mu)   # N per μ
    assert np.all(np.isfinite(data["error"])) and np.all(np.isfinite(data["seconds"]))


def test_table_point_and_its_build_cost(runs):
    data = runs[0.5]
    t = _points(data, "table")
    assert t["evaluations"].tolist() == [0] and t["error"].size == 1
    # the table's reported bound holds against the reference (independent of the table)
    assert t["error"][0] <= t["E_error"][0] + data["reference_error"]
    assert data["table_build_evaluations"] > 0 and data["table_build_seconds"] > 0


def test_methods_that_do_not_apply_are_listed_with_the_reason():
    values = {"ndf": "gtr", "alpha": 0.3, "fresnel": "dielectric"}
    data = to.tradeoff(make_spec(**values).brdf(), _key(values), mu=[0.5], max_budget=64)
    reasons = {x["method"]: x["reason"] for x in data["not_applicable"]}
    assert set(reasons) == {"mc_vndf", "table"}
    assert "vndf" in reasons["mc_vndf"] and "fresnel=dielectric" in reasons["table"]
    assert set(data["methods"]) == {"quadrature", "mc_uniform", "mc_cosine", "mc_ndf"}
    aniso = {"ndf": "ggx", "alpha": 0.3, "alpha_y": 0.1}
    data = to.tradeoff(make_spec(**aniso).brdf(), _key(aniso), mu=[0.5], methods=["table"])
    assert data["methods"] == [] and "isotropic" in data["not_applicable"][0]["reason"]


def test_budgets_respect_max_budget():
    assert to.budgets("quadrature", 16) == [4, 8, 16]
    assert to.budgets("mc_ndf", 16) == [16]
    assert to.budgets("mc_ndf", 1000) == [16, 64, 256]


def test_reference_is_cached_only_when_complete():
    # μ that need refinement past the first comparison (GGX α = 0.01 near grazing needs
    # order 192), so that a zero budget really cuts the reference
    values, mu = {"ndf": "ggx", "alpha": 0.01}, [0.0, 0.01, 0.5]
    brdf, key = make_spec(**values).brdf(), _key(values)
    with budget.limit(0.0) as b:
        cut, cached = to.reference(brdf, key, mu)
    assert b.notes and not cached          # it was cut
    full, cached = to.reference(brdf, key, mu)
    assert not cached                      # the cut one was not kept
    again, cached = to.reference(brdf, key, mu)
    assert cached and np.array_equal(again["E"], full["E"])


def test_time_budget_stops_points_with_a_note():
    values = {"ndf": "ggx", "alpha": 0.2}
    brdf, key = make_spec(**values).brdf(), _key(values)
    mu = np.linspace(0.0, 1.0, 129)
    t0 = time.perf_counter()
    with budget.limit(0.3):
        data = to.tradeoff(brdf, key, mu=mu, max_budget=65536,
                           methods=["quadrature", "mc_cosine", "mc_vndf"])
    assert time.perf_counter() - t0 < 2.0          # 0.3 s asked; one point may overrun
    assert not data["complete"] and "time budget" in data["note"]
    assert len(data["error"]) > 0                  # the cheap points were measured
    assert max(data["budget"]) < 65536
