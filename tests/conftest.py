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

