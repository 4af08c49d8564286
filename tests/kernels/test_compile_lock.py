"""Two processes that need the same model's loops on an empty numba cache (a clean
checkout's test workers, a server and its tests) compile them once: the other waits for
the lock (app/kernels/compose.py, ``compiling``) and loads what the first cached."""
from __future__ import annotations

import os
import subprocess
import sys
from pathlib import Path

ROOT = Path(__file__).resolve().parents[2]

# compiles (or loads) the default model's loops; prints how many of its three loops
# came from numba's cache
WARM = """
from app import kernels
from app.kernels import compose
from app.kernels.kernel import Kernel
from app.model import make_spec
c = kernels.components(make_spec().brdf())
module = compose.load(c)
with compose.compiling(module):
    Kernel(c, module).warm()
print(sum(min(1, sum(loop.stats.cache_hits.values())) for loop in (module.f_loop, module.albedo_rows, module.smith_h)))
"""


def test_one_process_compiles_a_model_the_other_loads_it(tmp_path):
    env = {**os.environ, "BRDF_KERNEL_DIR": str(tmp_path)}        # an empty cache
    procs = [subprocess.Popen([sys.executable, "-c", WARM], env=env, cwd=ROOT, text=True,
                              stdout=subprocess.PIPE, stderr=subprocess.PIPE) for _ in range(2)]
    outs = [p.communicate(timeout=600) for p in procs]
    assert all(p.returncode == 0 for p in procs), [err[-2000:] for _, err in outs]
    loaded = sorted(int(out.split()[-1]) for out, _ in outs)
    assert loaded == [0, 3]          # one compiled all three loops, the other loaded all three
