"""A model's loops compile by use (kernel.PARTS): a table build compiles the albedo's
quadrature rows and not the loops that evaluate f, and evaluating f compiles no albedo
rows. The check runs in a process of its own (the suite's kernel directory: loops another
test compiled are loaded, not compiled, and count the same) with an empty table cache, and
reads which of the generated modules' loops that process compiled or loaded."""
from __future__ import annotations

import json
import os
import subprocess
import sys
from pathlib import Path

import pytest

from app import kernels

ROOT = Path(__file__).resolve().parents[2]

pytestmark = pytest.mark.skipif(not kernels.ENABLED, reason="numba is not installed")

# builds one E(μ, α) table of a model outside any request (as the background builder
# does), then evaluates f of another model; prints which loops of each module compiled
CHECK = """
import json
from app import kernels
from app.integrate.tables import store, table as tables
from app.kernels import compose
from app.model import make_spec
lobe = make_spec(ndf="beckmann", fresnel="none").brdf()
key = tables.table_key(lobe, None)
store.table(key)
other = make_spec(ndf="ggx", fresnel="schlick").brdf()
kernels.compile_now(other, "f")
def compiled(brdf):
    module = compose.load(kernels.components(brdf))
    return {name: len(getattr(module, name).signatures) > 0
            for name in ("f_loop", "f_deg_loop", "albedo_rows", "smith_h")}
print(json.dumps({"table": compiled(lobe), "f": compiled(other)}))
"""


def test_a_table_build_compiles_only_the_albedo_loops_and_f_only_its_own(tmp_path):
    env = {**os.environ, "BRDF_CACHE_DIR": str(tmp_path / "tables")}
    out = subprocess.run([sys.executable, "-c", CHECK], env=env, cwd=ROOT, text=True,
                         capture_output=True, timeout=600)
    assert out.returncode == 0, out.stderr[-3000:]
    seen = json.loads(out.stdout.strip().splitlines()[-1])
    assert seen["table"] == {"f_loop": False, "f_deg_loop": False, "albedo_rows": True,
                             "smith_h": True}
    assert seen["f"] == {"f_loop": True, "f_deg_loop": True, "albedo_rows": False,
                         "smith_h": True}
