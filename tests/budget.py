"""The settings of the apps the tests build: a generous time budget.

Tests check results, not speed (speed is measured side by side in bench/). With the
deployment default (BRDF_MAX_SECONDS = 10), a request whose result a test checks was
cut, or a table build refused, whenever the shared machine was busy: measured with a
second test run and a benchmark beside it, a Beckmann table's build was predicted at
~4 s after 6 s spent on its F = 1 table, and two furnace tests failed on the budget,
not on the physics. The budget's own behaviour is tested with tiny budgets, which cut
deterministically (tests/api/test_advise_api.py, test_tradeoff_api.py,
test_albedo_methods_api.py, tests/robustness/test_hardening.py).
"""
from __future__ import annotations

from app.config import Settings

#: seconds one request may compute in the tests' apps: far above any request's
#: unloaded time (the slowest, a slow-lobe table build, ~10 s), far below a hang.
TEST_MAX_SECONDS = 300.0


def settings_for_tests(**overrides) -> Settings:
    """Settings() with the tests' time budget (and any limits a test sets)."""
    return Settings(**{"max_seconds": TEST_MAX_SECONDS, **overrides})
