"""The checks view's computations (app/checks.py): docs/conventions.md's identities computed
numerically must hold where the physics says they do, fail where it says they do not,
and report an error that covers the true one.

Expected values are docs/conventions.md's closed forms (1, n·v, n·v, 1), not the code's output; the
albedo rows are checked against the independent brute-force cubature of
tests/reference.py; the area element of row 4 against mpmath differentiation.
"""
from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

from app.analysis import checks
from app.integrate import slope_quadrature as sq
from app.integrate import budget
from app.model import make_spec
from app.physics.ndf import NDFS
from app.physics.vectors import direction_deg
from tests.reference import albedo_brute_force

# α of the brief (the API's range ends and one between) and one anisotropic pair.
ALPHAS = [(1e-4, None), (0.05, None), (1.0, None), (0.05, 0.5)]
SMITH_ROWS = ("1", "2", "3", "4")


def exact_masking(ndf: str) -> str:
    """Smith's exact Λ for the NDF: ``smith``, except where the NDF's Λ is an
    approximation (Blinn-Phong: Walter's Beckmann substitution) — ``smith_numeric``."""
    return "smith" if NDFS[ndf].smith_exact else "smith_numeric"


def by_id(data: dict) -> dict[str, dict]:
    keys = [k for k in data if isinstance(data[k], list)]
    return {rid: {k: data[k][i] for k in keys} for i, rid in enumerate(data["id"])}


def cases():
    for ndf in NDFS:
        for ax, ay in ALPHAS:
            if ay is None or NDFS[ndf].anisotropic:
                yield pytest.param(ndf, ax, ay, id=f"{ndf}-{ax:g}" + (f"-{ay:g}" if ay else ""))


@pytest.mark.parametrize("ndf, ax, ay", list(cases()))
def test_rows_1_to_4_hold_with_exact_smith(ndf, ax, ay):
    theta, phi = (60.0, 0.0) if ay is None else (70.0, 30.0)
    spec = make_spec(ndf=ndf, alpha=ax, alpha_y=ay, masking=exact_masking(ndf))
    rows = by_id(checks.checks(spec, theta, phi, SMITH_ROWS))
    mu = math.cos(math.radians(theta))
    closed_form = {"1": 1.0, "2": mu, "3": mu, "4": 1.0}      # docs/conventions.md identities 1–4
    for rid, expected in closed_form.items():
        r = rows[rid]
        assert r["expected"] == pytest.approx(expected, abs=1e-15)
        assert r["holds"] is True, (rid, r)
        # Blinn-Phong's D = m_z^{α_p} (α_p = 2e8 at α = 1e-4) amplifies the rounding of
        # m_z to ~1e-8 (the module's ROUNDING_FLOOR note); everything else is far closer.
        assert abs(r["value"] - expected) <= 2e-8, (rid, r)
        assert r["error"] < 1e-8 and r["evaluations"] > 0


@pytest.mark.parametrize("model", [dict(ndf="beckmann", masking="walter", alpha=0.5),
                                   dict(ndf="ggx", masking="schlick_direct", alpha=0.3)])
def test_an_approximate_masking_fails_row_3(model):
    """The check can fail: Walter's Λ (Beckmann) and Schlick-GGX's are not Smith's, so
    ∫ G1 D (v·m)⁺ dm ≠ n·v, by far more than the row's error."""
    rows = by_id(checks.checks(make_spec(**model), 60.0, 0.0, ("3", "4")))
    for rid in ("3", "4"):
        r = rows[rid]
        assert r["holds"] is False
        assert abs(r["difference"]) > 1e3 * (r["error"] + checks.HOLD_TOLERANCE)
        assert "approximates Smith" in r["note"]


def test_identity_3_difference_is_the_masking_error():
    """Row 3 = G1_model(v) ∫ D (v·m)⁺ dm and ∫ D (v·m)⁺ dm = n·v / G1_exact(v): the
    difference is n·v (G1_model/G1_exact − 1), with G1_exact from the closed form of
    Beckmann's Λ (Walter 2007 eq. 25) in mpmath and Walter's fit (eq. 27) by hand."""
    theta, alpha = 60.0, 0.5
    mu = mp.cos(mp.radians(theta))
    a = mu / (alpha * mp.sin(mp.radians(theta)))
    lam_exact = (mp.exp(-a * a) / (a * mp.sqrt(mp.pi)) - mp.erfc(a)) / 2
    lam_walter = (1 - 1.259 * a + 0.396 * a * a) / (3.535 * a + 2.181 * a * a)
    expected_diff = float(mu * ((1 + lam_exact) / (1 + lam_walter) - 1))
    r = by_id(checks.checks(make_spec(ndf="beckmann", masking="walter", alpha=alpha), theta,
                            0.0, ("3",)))["3"]
    assert r["difference"] == pytest.approx(expected_diff, rel=1e-9)


def test_separable_loses_more_energy_at_alpha_1():
    """Identity 6 integrated: 1 − E_sep ≥ 1 − E_hc, by a visible margin at α = 1; both
    albedos against the brute-force cubature of the definition (tests/reference.py)."""
    spec = make_spec(alpha=1.0, fresnel="schlick", kd=0.3)       # F and kd are dropped
    rows = by_id(checks.checks(spec, 60.0, 0.0, ("7", "7-loss")))
    loss = rows["7-loss"]
    assert loss["holds"] is True and loss["relation"] == "≥"
    assert loss["difference"] > 0.01 > loss["error"]
    refs = {}
    for g2 in ("separable", "height_correlated"):
        brdf = make_spec(alpha=1.0, fresnel="none", kd=0.0, g2=g2).brdf()
        refs[g2] = float(albedo_brute_force(brdf, 0.5, 0.0, tol=1e-9)[0])
    assert loss["value"] == pytest.approx(1 - refs["separable"], abs=1e-7)
    assert loss["expected"] == pytest.approx(1 - refs["height_correlated"], abs=1e-7)
    e = rows["7"]
    assert e["holds"] is True and e["value"] == pytest.approx(refs["height_correlated"], abs=1e-7)
    assert e["value"] < 1 - 0.1            # α = 1 loses >10 % of the energy


def test_compensated_furnace_within_table_error():
    spec = make_spec(ndf="ggx", alpha=0.5, multiscatter="kulla_conty")
    r = by_id(checks.checks(spec, 60.0, 0.0, ("7-furnace",)))["7-furnace"]
    assert r["holds"] is True
    assert abs(r["value"] - 1.0) <= r["error"] < 1e-4       # the table's measured error


@pytest.mark.parametrize("model, why", [
    (dict(alpha=0.3, alpha_y=0.1), "anisotropic"),
    (dict(ndf="beckmann", masking="walter"), "approximate"),
    (dict(alpha=0.3), "multiscatter=kulla_conty"),
])
def test_furnace_says_why_it_does_not_apply(model, why):
    r = by_id(checks.checks(make_spec(**model), 60.0, 0.0, ("7-furnace",)))["7-furnace"]
    assert r["value"] is None and r["holds"] is None and why in r["note"]


def test_only_the_rows_asked_are_computed():
    data = checks.checks(make_spec(), 45.0, 0.0, ["4", "1"])
    assert data["id"] == ["1", "4"] and data["row_order"] == "1, 4"
    assert all(len(v) == 2 for v in data.values() if isinstance(v, list))
    assert set(data["seconds_by_row"]) == {"1", "4"}
    assert data["total_evaluations"] == sum(data["evaluations"])


@pytest.mark.parametrize("ndf, ax, ay, theta, phi", [
    ("beckmann", 0.05, 0.5, 60.0, 30.0), ("ggx", 1e-4, 1.0, 75.0, 10.0),
    ("beckmann", 1.0, 1.0, 89.9, 200.0), ("student_t", 1.0, 0.1, 89.9, 200.0)])
def test_reported_error_covers_the_true_one_at_low_order(monkeypatch, ndf, ax, ay, theta, phi):
    """Cut at order 32 (vs 16), before convergence: |value − closed form| ≤ error."""
    monkeypatch.setattr(sq, "ORDER_MAX", 32)
    spec = make_spec(ndf=ndf, alpha=ax, alpha_y=ay)
    for r in by_id(checks.checks(spec, theta, phi, SMITH_ROWS)).values():
        assert abs(r["difference"]) <= r["error"], r


def test_time_budget_stops_refinement_with_a_note():
    spec = make_spec(ndf="beckmann", alpha=0.5)      # needs order 128 to reach 1e-11
    with budget.limit(0.0):
        data = checks.checks(spec, 60.0, 0.0, ("1",))
    assert data["complete"] is False and "BRDF_MAX_SECONDS" in data["budget_note"]
    assert "time budget" in data["note"][0] and data["holds"][0] is True


def test_albedo_rows_stop_at_their_time_share_with_a_note(monkeypatch):
    monkeypatch.setattr(checks, "ALBEDO_SECONDS", 0.0)
    spec = make_spec(ndf="ggx", alpha=1e-4, alpha_y=1.0)        # needs the highest order
    r = by_id(checks.checks(spec, 60.0, 0.0, ("7",)))["7"]
    assert "albedo stopped before reaching tol" in r["note"]
    assert r["holds"] is True and r["error"] > checks.ALBEDO_TOL   # the coarser, honest error


@pytest.mark.parametrize("model", [dict(ndf="student_t", gamma=1.7, alpha=0.05),
                                   dict(ndf="gtr", gamma=0.5, alpha=0.01),
                                   dict(ndf="exp_power", p=0.25, alpha=1.0)])
def test_long_tails_hold_with_an_honest_error(model):
    """Tails heavier than GGX's (Student-t γ < 2: the first moment of the slopes
    converges like r̃^{3−2γ}), a GTR whose mass sits at r̃ ~ 1/α, an exponential power
    with p = ¼: rows 1–3 hold, against the closed forms, within the reported error."""
    rows = by_id(checks.checks(make_spec(**model), 60.0, 0.0, ("1", "2", "3")))
    for rid, expected in (("1", 1.0), ("2", 0.5), ("3", 0.5)):
        r = rows[rid]
        assert r["holds"] is True, r
        assert abs(r["value"] - expected) <= r["error"] + checks.HOLD_TOLERANCE
        assert r["error"] < 1e-2
