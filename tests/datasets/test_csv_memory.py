"""A samples CSV leaves nothing behind that only the cycle collector would free (issue 36).

np.savetxt's writer holds the file it writes to in a reference cycle; with the text
left in an open StringIO, each model.csv export kept its 16 MB text in the heavy pool's
worker until the collector's next run, every ~22 jobs there (+15.6 MB RSS a request).
The collector is off while the calls run, as it in effect was between those runs: what
the calls leave is then what reference counting alone does not free. Only allocations made
under tabulate count (other threads of the test process allocate meanwhile: the
compiled loops' loader imported llvmlite during a first version of this test).
"""
import gc
import tracemalloc

import numpy as np

from app import kernels
from app.datasets import tabulate
from app.model import make_spec

#: calls measured: each kept its whole text before the fix (each takes ~0.5 s traced)
CALLS = 2
#: a small grid, 19 θ_i × 19 θ_o × 6 φ_o = 2166 rows (~80 kB of text a call)
N_THETA, N_PHI = 19, 6
#: bytes a call may leave for the collector: numpy's per-call WriteWrap class and its
#: bound methods (5.1 kB measured), not the text (a call left 76 kB before the fix)
LEFT_BYTES = 20_000
#: frames kept per allocation: enough to reach tabulate from the StringIO's write
#: (savetxt_text → np.savetxt → WriteWrap.write → .write_normal → StringIO.write)
FRAMES = 6
#: the allocations that count: those with samples_csv's module on their stack
UNDER_TABULATE = [tracemalloc.Filter(True, tabulate.__file__, all_frames=True)]


def _held() -> int:
    """Bytes now held by allocations made under tabulate."""
    return sum(s.size for s in tracemalloc.take_snapshot().filter_traces(UNDER_TABULATE)
               .statistics("filename"))


def test_samples_csv_leaves_no_text_behind():
    brdf = make_spec().brdf()
    theta, phi = np.linspace(0.0, 90.0, N_THETA), np.arange(N_PHI) * 360.0 / N_PHI
    with kernels.disabled():       # the numpy path: no compiling thread started for this
        tabulate.samples_csv(brdf, theta, phi)      # imports and caches: once
        gc.collect()
        gc.disable()
        tracemalloc.start(FRAMES)
        try:
            before = _held()
            for _ in range(CALLS):
                size = len(tabulate.samples_csv(brdf, theta, phi))
            left = (_held() - before) / CALLS
        finally:
            tracemalloc.stop()
            gc.enable()
    assert left < LEFT_BYTES, (
        f"each samples CSV of {size} characters left {left:.0f} bytes for the cycle collector")
