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


def pytest_xdist_auto_num_workers(config):
    """``-n auto``: half again as many workers as cores. About a third of the suite waits
    on a browser, a compiler or a server in another process, so a core per worker leaves
    the cores idle part of the time (2 cores: 3 workers)."""
    return max(1, (3 * len(os.sched_getaffinity(0)) + 1) // 2) if hasattr(os, "sched_getaffinity") \
        else max(1, (3 * (os.cpu_count() or 1) + 1) // 2)
