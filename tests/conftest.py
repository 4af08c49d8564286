"""The whole suite runs with its own empty cache directory (XDG_CACHE_HOME, inherited by
the servers it starts; Hypothesis' directory goes there too): the E(μ, α) tables a server
persists there must not come from an earlier run on the same machine, or a test of the
first build, the background builder or the honest fallback would see a table it did not
build (those tests give their servers a directory of their own)."""
from __future__ import annotations

import os
import shutil
import tempfile

import pytest
from hypothesis.configuration import set_hypothesis_home_dir

#: One directory for the whole run, made by the first process (xdist's controller, whose
#: environment its workers inherit): a table or a compiled model one worker made is found
#: by the other, as by a server's workers (the store locks and replaces whole files). With
#: a directory each, the two workers built the same tables and compiled the same models
#: twice (27 of 121 compiles in a run, ~5-10 s of CPU each, on a CPU-bound suite).
_OWNER = "BRDF_TESTS_CACHE" not in os.environ
if _OWNER:
    os.environ["BRDF_TESTS_CACHE"] = tempfile.mkdtemp(prefix="brdf-tests-cache-")
_CACHE = os.environ["BRDF_TESTS_CACHE"]
os.environ["XDG_CACHE_HOME"] = _CACHE
os.environ.pop("BRDF_CACHE_DIR", None)
# Hypothesis (under schemathesis) keeps its example database and caches in ./.hypothesis by
# default: the checkout. Tests write nothing there, so it goes with the run's cache.
set_hypothesis_home_dir(os.path.join(_CACHE, "hypothesis"))


@pytest.fixture(scope="session", autouse=True)
def one_heavy_pool_per_process():
    """One heavy-work pool (app/work) for each test process, as a server has one for its
    life. Each in-process app's lifespan (a TestClient) spawns the pool's worker a second
    after it starts and kills it at its shutdown: ~15 spawns in tests/api alone, ~2.5 CPU-s
    each (an interpreter importing the application), most for modules that never run heavy
    work, on a CPU-bound suite. The lifespan's own shutdown is tested where it matters:
    a real server under SIGTERM (tests/robustness/test_sigterm.py) and HeavyPool.close
    (tests/robustness/test_heavy_pool.py)."""
    from app import work
    with pytest.MonkeyPatch.context() as mp:
        mp.setattr(work, "close", lambda: None)
        yield
    work.close()


def pytest_unconfigure(config):
    if _OWNER:
        shutil.rmtree(_CACHE, ignore_errors=True)


#: xdist workers per core for ``-n auto``. One a core was right while the suite was
#: CPU-bound (CI 809 s with two workers against 873 s with three, 2026-12-04). Now much
#: of it waits (servers starting, Chromium, the heavy pool's worker processes): two
#: workers on 2 cores ran it in 1951 s wall with 1898 s of CPU, three in 1549 s
#: (2026-12-06) but twice failed the embeds' 60 s wait for the tradeoff view (and, at
#: load 10, other waits): one a core, until those waits stop depending on the load.
WORKERS_PER_CORE = 1


def pytest_xdist_auto_num_workers(config):
    """``-n auto`` (pyproject's addopts): WORKERS_PER_CORE workers a usable core."""
    cores = len(os.sched_getaffinity(0)) if hasattr(os, "sched_getaffinity") else os.cpu_count() or 1
    return max(1, round(cores * WORKERS_PER_CORE))


#: Test files (or node-id prefixes) that take tens of seconds each: run first, so that the
#: xdist workers do not end the run with one of them alone on a long tail (the README's
#: export snippets and the fuzzing came last in collection order).
SLOW_FIRST = (
    "tests/test_readme.py", "tests/robustness/test_fuzz_api.py", "tests/packaging/",
    "tests/kernels/", "tests/robustness/test_warmup.py", "tests/test_quantities.py",
    "tests/shader/test_lut.py", "tests/environment/test_estimator.py",
    "tests/e2e/test_exports.py",
)


def pytest_collection_modifyitems(session, config, items):
    """Known-slow tests first (a stable sort: the order within each group is kept)."""
    items.sort(key=lambda item: not item.nodeid.startswith(SLOW_FIRST))
