"""GET /api/v1/albedo with method, order, samples, seed and multiscatter.

References: the quadrature at a tight tolerance (tested on its own against an
independent brute-force cubature, tests/physics/test_albedo.py), the white furnace
(docs/identities.md §7) and the closed form F_avg = (20 f0 + 1)/21 of Schlick (p = 5,
f90 = 1; docs/conventions.md §5).
"""
import numpy as np
import pytest

from app.config import Settings
from app.main import create_app

from .conftest import TestClient
from tests.finite import finite_json

MU = "0.02,0.3,0.7,1"


def get(client, url, status=200):
    r = client.get(url)
    assert r.status_code == status, (url, r.status_code, r.text)
    return finite_json(r.text)


@pytest.fixture(scope="module")
def reference(client):
    body = get(client, f"/api/v1/albedo?mu={MU}&alpha=0.4&tol=1e-7")
    return np.array(body["E"]), np.array(body["E_error"])


@pytest.mark.parametrize("method", ["mc_uniform", "mc_cosine", "mc_ndf", "mc_vndf"])
def test_monte_carlo_agrees_within_its_standard_error(client, reference, method):
    """Each of 4 μ within 5 standard errors: a false failure has probability ~2e-6 per
    point for a Gaussian estimate (the coverage itself is tested in
    tests/physics/test_montecarlo.py)."""
    body = get(client, f"/api/v1/albedo?mu={MU}&alpha=0.4&method={method}&samples=20000&seed=3")
    E, err = np.array(body["E"]), np.array(body["E_error"])
    ref, ref_err = reference
    assert body["method"] == method and body["samples"] == 20000 and body["seed"] == 3
    assert body["evaluations"] >= 4 * 20000
    assert np.all(err > 0)
    assert np.all(np.abs(E - ref) <= 5 * err + ref_err), (E - ref, err)


def test_seed_reproduces_and_changes(client):
    a = get(client, f"/api/v1/albedo?mu={MU}&alpha=0.4&method=mc_cosine&samples=500&seed=1")
    b = get(client, f"/api/v1/albedo?mu={MU}&alpha=0.4&method=mc_cosine&samples=500&seed=1")
    c = get(client, f"/api/v1/albedo?mu={MU}&alpha=0.4&method=mc_cosine&samples=500&seed=2")
    assert a["E"] == b["E"] and a["E"] != c["E"]


def test_table_within_its_reported_error(client, reference):
    body = get(client, f"/api/v1/albedo?mu={MU}&alpha=0.4&method=table")
    ref, ref_err = reference
    assert body["method"] == "table" and body["evaluations"] == 0
    assert body["table"]["size"] and body["table"]["build_seconds"] > 0
    err = np.array(body["E_error"])
    assert np.all(np.abs(np.array(body["E"]) - ref) <= err + ref_err)


def test_fixed_order_costs_less_and_says_so(client, reference):
    low = get(client, f"/api/v1/albedo?mu={MU}&alpha=0.4&order=4")
    high = get(client, f"/api/v1/albedo?mu={MU}&alpha=0.4&order=64")
    ref, ref_err = reference
    for body in (low, high):
        # the bound is a bound, whatever the order
        assert np.all(np.abs(np.array(body["E"]) - ref) <= np.array(body["E_error"]) + ref_err)
    assert np.max(low["E_error"]) > np.max(high["E_error"])
    assert low["order"] == [8] * 4 and high["order"] == [128] * 4


def test_auto_names_the_method_it_chose(client):
    table = get(client, "/api/v1/albedo?mu=0.5&alpha=0.4&fresnel=none&method=table")
    bound = table["E_error"][0]
    loose = get(client, f"/api/v1/albedo?mu=0.5&alpha=0.4&fresnel=none&method=auto&tol={min(1e-2, 2 * bound)}")
    tight = get(client, f"/api/v1/albedo?mu=0.5&alpha=0.4&fresnel=none&method=auto&tol={bound / 10}")
    assert loose["requested_method"] == "auto" and loose["method"] == "table"
    assert tight["method"] == "quadrature" and tight["E_error"][0] <= bound / 10
    assert "≤ tol" in loose["auto_reason"] and "> tol" in tight["auto_reason"]
    assert "auto_reason" not in table


def test_auto_says_why_it_took_the_quadrature():
    """A table too slow to build within the request (it is queued for the background
    builder), or none for the model: auto takes the quadrature and its reason names the
    cause (a lobe whose table no other test builds: GTR's numpy integrand at an odd γ)."""
    tight = TestClient(create_app(Settings(max_seconds=0.3)))
    slow = get(tight, "/api/v1/albedo?mu=0.5&ndf=gtr&gamma=1.2345&g2=separable&fresnel=none"
                      "&alpha=0.3&method=auto&tol=1e-2")
    assert slow["method"] == "quadrature"
    assert slow["auto_reason"].startswith("no table yet") and "table" in slow["auto_reason"]
    none = get(tight, "/api/v1/albedo?mu=0.5&fresnel=dielectric&method=auto&tol=1e-3")
    assert none["method"] == "quadrature" and none["auto_reason"].startswith("no table")


@pytest.mark.parametrize("ndf", ["ggx", "beckmann"])
def test_compensated_white_furnace(client, ndf):
    """F = 1 with Kulla-Conty: E = 1 within the table's error (identity 7), while the
    single-scattering albedo it reports is visibly below 1 at α = 0.9. (Every NDF's
    furnace: tests/physics/test_compensation.py, with small tables.)"""
    body = get(client, f"/api/v1/albedo?mu=0.05,0.5,1&ndf={ndf}&alpha=0.9&fresnel=none"
                       "&multiscatter=kulla_conty")
    E = np.array(body["E"])
    bound = body["compensation_error"] + np.array(body["E_single_error"])
    assert np.all(np.abs(E - 1.0) <= bound), (E - 1, bound)
    assert np.min(body["E_single"]) < 0.95
    assert body["F_avg"] == 1.0 and 0 < body["E_avg_single"] < 1


def test_compensated_schlick_reports_F_avg_closed_form(client):
    f0 = 0.3
    body = get(client, f"/api/v1/albedo?mu=0.5&alpha=0.6&f0={f0}&multiscatter=kulla_conty")
    assert body["F_avg"] == pytest.approx((20 * f0 + 1) / 21, rel=1e-12)
    # compensation adds energy, never more than the single scattering lost
    assert body["E_single"][0] < body["E"][0] < 1.0


def test_albedo_figure_shows_both_curves_with_compensation(client):
    fig = get(client, "/api/v1/figures/albedo?n=5&alpha=0.8&multiscatter=kulla_conty")
    names = [t.get("name", "") for t in fig["data"]]
    assert any(n.startswith("E(μ) with compensation") for n in names)
    assert any(n.startswith("E<sub>single</sub>") for n in names)
    plain = get(client, "/api/v1/figures/albedo?n=5&alpha=0.8&method=mc_ndf")
    assert any("standard error" in t.get("name", "") for t in plain["data"])


@pytest.mark.parametrize("query, param", [
    ("method=table&alpha=0.3&alpha_y=0.1", "method"),          # tables are isotropic
    ("method=table&fresnel=dielectric", "method"),             # tabulated for F = 1 / Schlick
    ("method=mc_vndf&ndf=student_t", "method"),                # no visible-normal sampler
    ("method=mc_ndf&order=8", "order"),                        # order is the quadrature's
    ("method=quadrature&samples=64", "samples"),               # samples, seed: Monte Carlo's
    ("samples=64", "samples"),                                 # (the default method too)
    ("method=table&seed=1", "seed"),
    ("method=auto&samples=64", "samples"),
    ("order=1", "order"),
    ("order=100000", "order"),
    ("method=mc_ndf&samples=1", "samples"),
    ("method=mc_ndf&samples=-5", "samples"),
    ("method=simpson", "method"),
])
def test_bad_method_arguments_are_named(client, query, param):
    body = get(client, f"/api/v1/albedo?mu=0.5&{query}", status=422)
    assert any(param in ".".join(map(str, e["loc"])) for e in body["detail"]), body


def test_monte_carlo_work_limit_is_named():
    small = TestClient(create_app(Settings(max_mc_evaluations=1000)))
    body = get(small, "/api/v1/albedo?mu=0.1,0.5&method=mc_cosine&samples=600", status=422)
    msg = body["detail"][0]["msg"]
    assert "BRDF_MAX_MC_EVALUATIONS" in msg and "1000" in msg


def test_a_table_too_slow_for_the_request_is_built_outside_it(monkeypatch):
    """method=table needs the whole E(μ, α) table; one predicted (from a probe of a few
    E(μ)) not to build within the request is queued for the background builder and the
    request answered at once with 503 + Retry-After naming the table — not a worker busy
    for minutes (GGX with smith_numeric took 108 s before), nor a 422 for valid input. A
    shape no other test uses, so no cached table. (Kulla-Conty no longer waits for it: it
    builds E(μ) at the lobe's own α in the request, tests/integrate/test_alpha_slice.py.)"""
    from app.integrate.tables import store as table_store, table
    # 2 s: the build (GTR, direction-correlated: minutes on numpy) is far beyond it
    tight = TestClient(create_app(Settings(max_seconds=2.0)))
    table_store.start(None, keys=[])        # the builder a served app starts, no defaults
    # the queued build itself is not this test's subject: it fails at once
    monkeypatch.setattr(table, "build_for_key", lambda key, base=None: 1 / 0)
    # the request may probe a few E(μ) but never build this lobe's table grid (counted,
    # not timed: the machine's load is not this test's subject)
    real_build, built_here = table.build, []

    def counted_build(key, *args, **kwargs):
        if ("gamma", 1.37) in key[1]:
            built_here.append(key)
        return real_build(key, *args, **kwargs)

    monkeypatch.setattr(table, "build", counted_build)
    r = tight.get("/api/v1/albedo?n=3&method=table&ndf=gtr&gamma=1.37&alpha=0.4"
                  "&g2=direction_correlated&fresnel=none")
    assert r.status_code == 503, r.text
    assert int(r.headers["retry-after"]) >= 1
    msg = r.json()["detail"][0]["msg"]
    assert "table" in msg and "ndf=gtr" in msg and "being built" in msg
    assert built_here == []
    assert table_store.wait(60)
    table_store.stop()
