"""app/analysis/advise.py: the errors it reports are upper bounds of the albedo error it names,
checked against E computed apart — by tests/reference.albedo_brute_force (adaptive
cubature of f·cos over the hemisphere) at single points, and by the quadrature on a
grid 3-4× finer than the advice's — and its choices follow from those errors."""
from __future__ import annotations

import json

import numpy as np
import pytest

from app.analysis.advise import Scene, advise, single_changes
from app.integrate import budget
from app.integrate.albedo import albedo
from app.integrate.montecarlo import albedo_mc
from app.model import make_spec
from tests.reference import albedo_brute_force

#: the brute-force cubature's tolerance (its reported errors were ≤ 4e-9 at these points)
BRUTE_TOL = 1e-7


def entry(result: dict, label: str) -> dict:
    found = [e for e in result["alternatives"] if e["label"] == label]
    assert len(found) == 1, [e["label"] for e in result["alternatives"]]
    return found[0]


def brute_dE(model: dict, alt: dict, alpha: float, mu: float) -> float:
    """|E_alt − E_model| at one (α, μ), each by adaptive cubature of the definition."""
    e_ref, err_ref, _ = albedo_brute_force(make_spec(**model, alpha=alpha).brdf(), mu, tol=BRUTE_TOL)
    e_alt, err_alt, _ = albedo_brute_force(make_spec(**alt, alpha=alpha).brdf(), mu, tol=BRUTE_TOL)
    return abs(e_alt - e_ref) - err_ref - err_alt        # the least it can be


def quad_dE_max(model: dict, alt: dict, alphas, theta_deg) -> float:
    """max |E_alt − E_model| (plus both error bounds) by quadrature on a grid uniform in θ."""
    mu = np.cos(np.radians(theta_deg))
    worst = 0.0
    for a in alphas:
        r = albedo(make_spec(**model, alpha=a).brdf(), mu, tol=1e-6)
        s = albedo(make_spec(**alt, alpha=a).brdf(), mu, tol=1e-6)
        worst = max(worst, float(np.max(np.abs(s.E - r.E) - r.E_error - s.E_error)))
    return worst


def test_choices_offered_follow_the_registry():
    labels = lambda **m: [", ".join(f"{k}={v}" for k, v in c.items())     # noqa: E731
                          for c in single_changes(make_spec(**m).values)]
    assert labels(ndf="ggx") == ["masking=karis", "masking=schlick_direct", "masking=schlick_ibl",
                                 "g2=separable", "g2=hammon"]
    assert labels(ndf="beckmann") == ["masking=walter", "g2=separable"]   # Karis etc.: GGX only
    assert "masking=smith" in labels(ndf="gtr", alpha=0.3, masking="smith_numeric")
    assert labels(ndf="ggx", masking="karis", g2="separable", fresnel="schlick") == []
    assert labels(ndf="ggx", fresnel="conductor", multiscatter="kulla_conty")[-2:] == \
        ["fresnel=schlick", "multiscatter=none"]


def test_walter_accepted_for_beckmann_and_its_bound_holds():
    # Walter's rational Λ: error of E ~3e-3 at worst (grazing, small α); tol 1e-2.
    res = advise({"ndf": "beckmann"}, 1e-2, Scene(0.05, 1.0, 90.0))
    walter = entry(res, "masking=walter")
    assert walter["within_tol"] and walter["max_error"] <= 1e-2
    for alpha, mu in [(0.1, 0.03), (0.3, 0.1)]:
        assert walter["max_error"] >= brute_dE({"ndf": "beckmann"},
                                               {"ndf": "beckmann", "masking": "walter"}, alpha, mu)
    assert not entry(res, "g2=separable")["within_tol"]          # 3e-2 at grazing


def test_schlick_direct_rejected_for_ggx_at_one_percent():
    res = advise({"ndf": "ggx"}, 1e-2, Scene(0.05, 1.0, 90.0))
    sd = entry(res, "masking=schlick_direct")
    dE = brute_dE({"ndf": "ggx"}, {"ndf": "ggx", "masking": "schlick_direct"}, 0.1, 0.1)
    assert dE > 1e-2                                  # so rejecting it is right ...
    assert not sd["within_tol"] and sd["max_error"] >= dE     # ... and its bound covers it


@pytest.mark.parametrize("model, alt, scene", [
    # the case where the largest error grew most between the advice's nodes (1.48×)
    ({"ndf": "beckmann"}, {"masking": "walter"}, Scene(0.02, 0.2, 85.0)),
    ({"ndf": "ggx"}, {"masking": "karis"}, Scene(0.01, 1.0, 90.0)),
    ({"ndf": "ggx", "fresnel": "conductor"}, {"fresnel": "schlick"}, Scene(0.05, 1.0, 90.0)),
])
def test_max_error_holds_on_a_finer_grid(model, alt, scene):
    res = advise(model, 0.5, scene)
    e = next(x for x in res["alternatives"] if x["changes"] == alt)
    fine_alphas = np.geomspace(scene.alpha_min, scene.alpha_max, 4 * 6)          # 4× in α
    fine_theta = np.linspace(0.0, scene.theta_max_deg, 4 * 9)                    # 4× in θ
    fine = quad_dE_max(model, e["model"], fine_alphas, fine_theta)
    assert fine <= e["max_error"], (fine, e["max_error"])
    assert fine >= 0.25 * e["max_error"]     # the bound is not vacuous either (GRID_SAFETY 2)


def test_tiny_tol_keeps_the_current_model():
    res = advise({"ndf": "ggx", "alpha": 0.2}, 1e-4, Scene(0.1, 0.5, 80.0))
    assert res["changes"] == {} and res["max_error"] == 0.0 and res["relative_cost"] == 1.0
    assert res["recommendation"] == res["current"]
    assert make_spec(**res["recommendation"]).values["alpha"] == 0.2


def test_schlick_replaces_an_exact_fresnel_with_the_same_f0():
    res = advise({"fresnel": "dielectric", "ior": 1.5}, 0.1, Scene(0.05, 1.0, 80.0))
    e = entry(res, "fresnel=schlick")
    assert e["model"]["f0"] == pytest.approx(((1.5 - 1) / (1.5 + 1)) ** 2, rel=1e-12)   #
    assert "ior" not in e["model"]
    make_spec(**e["model"])                                       # feedable as it is
    make_spec(**res["recommendation"])
    if res["changes"]:
        assert res["max_error"] <= 0.1 and res["relative_cost"] < 1.0


def test_monte_carlo_bound_covers_its_deviation():
    with budget.limit(5.0):            # below the table's reserve: only Monte Carlo is rated
        res = advise({"ndf": "ggx", "fresnel": "none"}, 0.5, Scene(0.2, 0.4, 60.0),
                     albedo_methods=True)
    mc = [e for e in res["alternatives"] if e["kind"] == "albedo_method"
          and e["changes"]["albedo_method"] == "mc_vndf"]
    assert [e["changes"]["samples"] for e in mc] == [256, 1024, 4096]
    errors = [e["max_error"] for e in mc]
    assert errors[0] > errors[1] > errors[2]                   # σ ∝ 1/√N
    # another seed at a point of the range: its deviation from the quadrature is covered
    brdf = make_spec(ndf="ggx", fresnel="none", alpha=0.3).brdf()
    E_mc = albedo_mc(brdf, [0.6], sampler="vndf", samples=1024, seed=7).E[0]
    E_q = albedo(brdf, [0.6], tol=1e-7).E[0]
    assert abs(E_mc - E_q) <= errors[1]
    assert res["albedo_method"]["method"] in ("quadrature", "mc_vndf")
    assert "table" in res["note"]


def test_cut_by_the_budget_is_incomplete_and_finite():
    with budget.limit(0.0):
        res = advise({"ndf": "ggx"}, 1e-2, Scene(0.05, 1.0, 90.0))
    assert res["complete"] is False and "note" in res
    assert res["changes"] == {} and res["max_error"] == 0.0
    json.dumps(res, allow_nan=False)
