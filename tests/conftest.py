"""The whole suite runs with its own empty cache directory (XDG_CACHE_HOME, inherited by
the servers it starts; Hypothesis' directory goes there too): the E(μ, α) tables a server
persists there must not come from an earlier run on the same machine, or a test of the
first build, the background builder or the honest fallback would see a table it did not
build."""
from __future__ import annotations

import os
import shutil
import tempfile

from hypothesis.configuration import set_hypothesis_home_dir

_CACHE = tempfile.mkdtemp(prefix="brdf-tests-cache-")
os.environ["XDG_CACHE_HOME"] = _CACHE
os.environ.pop("BRDF_CACHE_DIR", None)
#: The compiled loops, unlike the tables, are code named by the fingerprint of their source:
#: one directory for the whole run, made by the first process (xdist's controller, whose
#: environment its workers inherit), so that a model compiled by one worker is loaded by
#: the other. With a directory each, the two workers compiled the same models twice (15 of
#: the first 60, ~5-10 s of CPU each). Tests of the compile itself set their own.
_KERNELS_OWNER = "BRDF_KERNEL_DIR" not in os.environ
if _KERNELS_OWNER:
    os.environ["BRDF_KERNEL_DIR"] = tempfile.mkdtemp(prefix="brdf-tests-kernels-")
# Hypothesis (under schemathesis) keeps its example database and caches in ./.hypothesis by
# default: the checkout. Tests write nothing there, so it goes with the run's cache.
set_hypothesis_home_dir(os.path.join(_CACHE, "hypothesis"))


def pytest_unconfigure(config):
    shutil.rmtree(_CACHE, ignore_errors=True)
    if _KERNELS_OWNER:
        shutil.rmtree(os.environ["BRDF_KERNEL_DIR"], ignore_errors=True)


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
