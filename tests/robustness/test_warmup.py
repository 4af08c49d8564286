"""The fast path is compiled before any request is timed (app/warmup.py).

CI runs a clean clone, where numba's on-disk cache is empty: a loop compiled inside the
first advice request made its first row ten times slower than the rest, the advice
predicted no time for the others and answered incomplete. These tests hold the two
parts of the fix: one compiled version per loop whatever arrays the callers pass
(writable or frozen), and a fresh process with an empty cache answering its first
heavy request whole within the default budget.
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

from app import warmup
from app.integrate import albedo_kernel
from app.model import make_spec
from app.physics import fast

ROOT = Path(__file__).resolve().parents[2]


def _signatures() -> dict[str, int]:
    return {name: len(k.signatures) for name, k in fast._kernels.items()}


# numba is in the test extras, so CI runs this; without numba (or with BRDF_FAST=0)
# there are no compiled loops to count. The fresh-process test below runs either way.
@pytest.mark.skipif(not fast.AVAILABLE, reason="numba absent or BRDF_FAST=0: no compiled loops")
def test_one_compiled_version_per_loop_for_writable_and_frozen_inputs():
    warmup.warm_up()
    loops = [*fast.F_LOOPS, *fast.F_GGX_LOOPS, *albedo_kernel.ROW_LOOPS]
    names = {f"{f.__module__}.{f.__qualname__}" for f in loops}
    assert names <= set(fast._kernels), "warm_up compiles every loop"
    before = _signatures()
    assert all(before[n] == 1 for n in names)

    frozen = np.array([[0.3, 0.1, 0.9], [0.0, 0.6, 0.8]])
    frozen.flags.writeable = False
    writable = frozen.copy()
    for ndf in ("ggx", "beckmann"):
        args = fast.spec_args(make_spec(ndf=ndf, roughness=0.5).brdf())
        for l, v in ((frozen, writable), (writable, frozen), (frozen, frozen)):
            f = fast.evaluate_f(args, l, v)
            assert np.all(np.isfinite(f))
        nodes = dict(cp=np.ones((2, 3)), sp=np.zeros((2, 3)), U=np.full((2, 3), 0.5),
                     V0=np.full((2, 3), 0.5))
        rule = np.array([0.25, 0.75])
        nodes["cp"].flags.writeable = False
        albedo_kernel.integrate(args[:7], writable, **nodes, head=rule, tail=rule, w_u=rule,
                                h=rule, dh=rule, use_log=False, w_psi=np.ones(3))
    assert _signatures() == before, "a call compiled a second version of a loop"


def test_fresh_process_with_empty_cache_answers_the_advice_whole(tmp_path):
    """The CI failure, reproduced: a new process, numba's cache empty, the app served
    without its lifespan (as the test client does), the advice's first request."""
    script = (
        "import json\n"
        "from fastapi.testclient import TestClient\n"
        "from app.main import create_app\n"
        "c = TestClient(create_app())\n"
        "r = c.get('/api/v1/advise', params={'alpha_min': 0.1, 'alpha_max': 0.4,"
        " 'theta_max_deg': 70, 'tol': 0.02})\n"
        "d = r.json()\n"
        "print(json.dumps({'status': r.status_code, 'complete': d.get('complete'),"
        " 'note': d.get('note')}))\n")
    env = {**os.environ, "NUMBA_CACHE_DIR": str(tmp_path), "BRDF_MAX_SECONDS": "10"}
    out = subprocess.run([sys.executable, "-c", script], cwd=ROOT, env=env, timeout=300,
                         capture_output=True, text=True, check=True)
    result = json.loads(out.stdout.strip().splitlines()[-1])
    assert result["status"] == 200
    assert result["complete"] is True, result["note"]
