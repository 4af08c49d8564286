"""The whole suite runs with its own empty cache directory (XDG_CACHE_HOME, inherited by
the servers it starts): the E(μ, α) tables a server persists there must not come from an
earlier run on the same machine, or a test of the first build, the background builder or
the honest fallback would see a table it did not build."""
from __future__ import annotations

import os
import shutil
import tempfile

_CACHE = tempfile.mkdtemp(prefix="brdf-tests-cache-")
os.environ["XDG_CACHE_HOME"] = _CACHE
os.environ.pop("BRDF_CACHE_DIR", None)


def pytest_unconfigure(config):
    shutil.rmtree(_CACHE, ignore_errors=True)


#: xdist workers per core for ``-n auto``. Three on 2 cores ran this machine's warm
#: suite in 708 s against 860 s for two, but CI (a clean clone: every compiled loop built
#: from an empty numba cache, in each worker and server at once) took 873 s with three
#: against 809 s with two, and its trade-off embed hung on a busy server: one a core
#: (BENCHMARKS.md, "The test suite").
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
