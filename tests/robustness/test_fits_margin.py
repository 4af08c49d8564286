"""A 413's "what would fit" fits (issue 36): asked again at the size it names, the same
work is admitted even when its cost, measured afresh by a probe that varies ~20 % from
one run to the next, reads 20 % higher (here: the same work under a budget 1.2× smaller).
At the edge of the budget (the suggestion before) a fresh probe reading a little higher
refused the suggestion itself.

The worker's own decision (app/work/costs.py under the request's budget) is made here
in-process: the pool only carries it to another process (tests/robustness/test_heavy_pool.py)."""
from __future__ import annotations

import re

import pytest
from starlette.datastructures import QueryParams

from app.api.http.query_route import read_query
from app.config import Settings
from app.errors import Busy, TooLarge
from app.export import build
from app.integrate import budget
from app.views import VIEWS
from app.work import costs, jobs

#: BRDF_MAX_SECONDS of these requests: small, so the 413 and its suggestion come cheap,
#: yet several times the probe's own seconds (a 64-pixel sphere)
SECONDS = 2.0
SPHERE = "environment=studio&model=principled&clearcoat=1&sheen=1&n=256"
#: how much higher than the first a fresh probe of the cost may read
PROBE_SPREAD = 1.2


def _state(query: str):
    return jobs.query_state(read_query(build.export_query(VIEWS["sphere_env"]), QueryParams(query)))


def _admit(query: str, seconds: float = SECONDS) -> None:
    """The worker's decision on the request before any work (jobs.view's first step)."""
    view = VIEWS["sphere_env"]
    q = jobs.rebuilt(build.export_query(view), _state(query))
    with budget.limit(seconds):
        costs.require_view(view, q, Settings(max_seconds=seconds))


def test_the_suggested_size_is_admitted_with_a_fresh_probe():
    with pytest.raises(TooLarge) as big:
        _admit(f"{SPHERE}&samples=61&roughness=0.5")
    assert big.value.param == "samples" and "BRDF_MAX_SECONDS=2" in big.value.message
    n = int(re.search(r"at samples=61, n ≤ (\d+)", big.value.message).group(1))
    assert 1 <= n < 256
    # a fresh probe (a roughness the cost does not depend on, but the probe's cache does),
    # under a budget as much smaller as the probe may read higher: admitted, or at most
    # "not now" (503: the probe itself took the time on a loaded machine), never "never"
    try:
        _admit(f"{SPHERE.replace('n=256', f'n={n}')}&samples=61&roughness=0.51", SECONDS / PROBE_SPREAD)
    except Busy:
        pass
