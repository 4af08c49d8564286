"""The requests that escaped the documented limits, each answered within its budget with
the right status. Time itself is measured in bench/worst_case.py; here what bounds it:
how much work a request does, how much memory it holds, and what is refused when."""
from __future__ import annotations

import threading
import time
import tracemalloc

import numpy as np
import pytest
from fastapi.testclient import TestClient

from app.config import Settings
from app.errors import Busy
from app.export import image
from app.integrate import budget, cost
from app.main import create_app
from app.physics import lambda_table, smith_integral, smith_table
from tests.budget import settings_for_tests


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(settings_for_tests()))


@pytest.fixture
def quadrature_directions(monkeypatch):
    """Counts the directions the direct Smith integral is evaluated at."""
    count = [0]
    real = smith_integral._integral

    def counted(ndf, mu, s, v0, order, with_slope=False):
        if threading.current_thread().name != "table-builder":   # not another test's build
            count[0] += int(np.size(mu))
        return real(ndf, mu, s, v0, order, with_slope)

    monkeypatch.setattr(smith_integral, "_integral", counted)
    smith_table._table.cache_clear()
    lambda_table._packed.cache_clear()    # holds the packed tables the compiled loops read
    return count


TABLE_BUILD = smith_table.TABLE_NODES + 1      # one table: its nodes and the grazing value


@pytest.mark.parametrize("url", [
    "/api/v1/albedo?n=257&tol=1e-7&alpha=1e-4&masking=smith_numeric&ndf=exp_power&p=0.25",
    "/api/v1/albedo?n=2&masking=smith_numeric&ndf=exp_power&p=0.3",
    "/api/v1/lobe3d?n_theta=500&n_phi=500&masking=smith_numeric",
])
def test_smith_numeric_costs_one_table_not_an_integral_per_direction(client, url, quadrature_directions):
    """The albedo held a worker 127 s at 5 GB and the 3-D lobe 4–50 s: the Smith integral
    ran at 192 nodes for every direction of every integrand point. Now at most one table
    of the NDF's shape is built, whatever the number of directions."""
    r = client.get(url)
    assert r.status_code == 200, r.text
    assert r.json().get("complete", True)
    # the table was built, by this request (counted) or by the start-up builder thread
    # (not counted: it may come first on a loaded machine), and nothing else was integrated
    assert smith_table._table.cache_info().currsize >= 1
    assert quadrature_directions[0] <= 2 * TABLE_BUILD


def test_a_full_batch_with_smith_numeric(client, quadrature_directions):
    n = Settings().max_batch
    rng = np.random.default_rng(3)
    body = {"masking": "smith_numeric", "quantities": ["f", "G2"],
            **{k: rng.uniform(0, 90, n).round(6).tolist() for k in
               ("theta_i_deg", "theta_o_deg", "phi_i_deg", "phi_o_deg")}}
    r = client.post("/api/v1/eval", json=body)
    assert r.status_code == 200, r.text[:300]
    assert len(r.json()["f"]) == n
    assert quadrature_directions[0] <= TABLE_BUILD


def test_monte_carlo_at_its_limit_holds_far_less_than_the_memory_budget(client):
    """n=32 × 65536 samples with smith_numeric needed more than 6 GiB (a 500 under a
    6 GiB cap): Python-visible allocations now peak far below BRDF_MAX_REQUEST_BYTES."""
    url = "/api/v1/albedo?n=32&samples=65536&method=mc_uniform&masking=smith_numeric"
    client.get("/api/v1/albedo?n=2&samples=64&method=mc_uniform&masking=smith_numeric")  # tables
    tracemalloc.start()
    try:
        r = client.get(url)
        peak = tracemalloc.get_traced_memory()[1]
    finally:
        tracemalloc.stop()
    assert r.status_code == 200, r.text
    assert peak < Settings().max_request_bytes / 2, peak


def test_work_above_the_memory_budget_is_413_naming_the_setting_before_any_work():
    small = TestClient(create_app(settings_for_tests(max_request_bytes=20_000_000)))
    r = small.get("/api/v1/albedo?n=32&samples=65536&method=mc_uniform")
    assert r.status_code == 413
    d = r.json()["detail"][0]
    assert d["loc"][-1] == "samples" and "BRDF_MAX_REQUEST_BYTES" in d["msg"]
    r = small.get("/api/v1/lobe3d?n_theta=500&n_phi=500")
    assert r.status_code == 413 and "BRDF_MAX_REQUEST_BYTES" in r.text


def test_work_beyond_the_whole_budget_is_413_and_beyond_what_is_left_503(monkeypatch):
    """Input that cannot fit whatever the load is a 413 naming BRDF_MAX_SECONDS; input that
    fits but arrives when the budget is mostly spent (the request waited) is a 503."""
    monkeypatch.setattr(cost, "seconds_per_evaluation", lambda brdf: 1e-4)   # 250 000 → 25 s
    with budget.limit(10.0):
        with pytest.raises(Exception) as too_large:
            cost.require_evaluations(None, 250_000, 0, "n_theta×n_phi", "the grid")
    assert getattr(too_large.value, "status", None) == 413
    assert "BRDF_MAX_SECONDS" in too_large.value.message
    with budget.limit(10.0) as b:
        b.start -= 9.0                                    # 9 of 10 s already spent
        with pytest.raises(Busy) as busy:
            cost.require_evaluations(None, 40_000, 0, "n_theta×n_phi", "the grid")   # 4 s
    assert busy.value.retry_after >= 1


def test_negligible_work_is_done_even_when_set_up_spent_the_budget(monkeypatch):
    """A request whose one-time set-up (loading compiled code on a loaded machine) spent
    its budget still does work predicted at a few milliseconds: refusing it would free the
    worker no sooner and cost the client a retry."""
    monkeypatch.setattr(cost, "seconds_per_evaluation", lambda brdf: 1e-7)   # 1000 → 0.1 ms
    with budget.limit(0.3) as b:
        b.start -= 5.0                                    # far past budget and grace
        cost.require_evaluations(None, 1000, 0, "n", "the curve")              # no Busy
    with budget.limit(0.3) as b:
        b.start -= 5.0
        with pytest.raises(Busy):
            cost.require_evaluations(None, 2_000_000, 0, "n", "the grid")      # 0.2 s: refused


class SlowRenderer(image.ImageRenderer):
    def _render(self, figure, opts):
        time.sleep(1.0)
        return b"\x89PNG"


def test_an_export_burst_is_refused_before_any_work_and_cheap_requests_go_on(monkeypatch):
    """100 concurrent PNG exports made a cheap /lobe on the same worker wait 90 s: exports
    now hold at most their queue's places, and the rest are 503 + Retry-After before
    their figure is computed (so they cost the server nothing)."""
    from app.export import build
    app = create_app(settings_for_tests())
    renderer = SlowRenderer()
    app.dependency_overrides[image.get_renderer] = lambda: renderer
    produced = []
    real_produce = build.produce
    monkeypatch.setattr(build, "produce", lambda *a, **k: produced.append(1) or real_produce(*a, **k))
    c = TestClient(app)
    c.get("/api/v1/health")
    statuses = []

    def export():
        r = c.get("/api/v1/figures/lobe.png?n=9")
        statuses.append((r.status_code, r.headers.get("retry-after")))

    burst = [threading.Thread(target=export) for _ in range(40)]
    for t in burst:
        t.start()
    assert c.get("/api/v1/lobe?n=9").status_code == 200
    for t in burst:
        t.join()
    ok = [s for s, _ in statuses if s == 200]
    busy = [ra for s, ra in statuses if s == 503]
    assert len(ok) + len(busy) == 40 and busy
    assert all(ra and int(ra) >= 1 for ra in busy)
    assert len(produced) == len(ok)          # no figure computed for a refused export
