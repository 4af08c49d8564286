"""Report the size of the runs: requests schemathesis sent, models and points swept."""
from __future__ import annotations

import sys


def _module(name: str):
    """A test module by its file name, whatever package path pytest imported it under."""
    return next((m for key, m in list(sys.modules.items()) if key.split(".")[-1] == name), None)


def pytest_terminal_summary(terminalreporter):
    module = _module("test_fuzz_api")
    calls = getattr(module, "CALLS", None)
    if calls:
        terminalreporter.write_line(
            f"schemathesis: {sum(calls.values())} requests over {len(calls)} operations "
            f"(fewest {min(calls.values())}, most {max(calls.values())})")
        seconds = getattr(module, "SECONDS", {})
        slow = sorted(seconds.items(), key=lambda kv: -kv[1])[:5]
        terminalreporter.write_line(
            "slowest: " + ", ".join(f"{k} {calls[k]}× {v:.1f} s" for k, v in slow))
    sweep = _module("test_extremes_sweep")
    size = getattr(sweep, "SIZE", None)
    if size and size["combinations"]:
        terminalreporter.write_line(
            f"extremes sweep: {size['combinations']} combinations, {size['models']} models, "
            f"{size['points']} (l, v) evaluations")
