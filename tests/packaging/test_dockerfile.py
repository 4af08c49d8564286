"""The Dockerfile's Python steps run against this checkout: the image's build compiles the
server's first models by a line of Python naming the application's functions, which a
rename left pointing at nothing (no image is built here; docker is not on the machine).
With BRDF_FAST=0 the step runs its imports and calls without compiling (seconds)."""
from __future__ import annotations

import os
import re
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]


def test_every_python_step_of_the_dockerfile_runs():
    steps = re.findall(r'^RUN python -c "(.*)"\s*$', (ROOT / "Dockerfile").read_text(), flags=re.M)
    assert steps, "the Dockerfile compiles the first models at build time"
    for code in steps:
        out = subprocess.run([sys.executable, "-c", code], cwd=ROOT, capture_output=True, text=True,
                             timeout=300, env={**os.environ, "BRDF_FAST": "0"})
        assert out.returncode == 0, (code, out.stderr[-2000:])
