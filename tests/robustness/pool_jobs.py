"""Jobs for the heavy-pool tests (tests/robustness/test_heavy_pool.py), in a module that
imports only the standard library: a spawned worker imports the module a job lives in
before it runs the job, and importing the test module (pytest, pydantic, the app) took
past a 2 s budget under the whole suite's load, cutting a 0.1 s job."""
from __future__ import annotations

import time


def spin(seconds: float) -> float:
    """Pure-Python CPU work (holds the GIL of whichever process runs it)."""
    end, x = time.perf_counter() + seconds, 0.0
    while time.perf_counter() < end:
        x += 1.0
    return seconds


def cheap() -> None:
    """A slider request's share of Python work: ~2 ms."""
    sum(i * i for i in range(20_000))


def square(x: int) -> int:
    return x * x
