"""Mitsuba 3's roughconductor (LLVM backend) on direction pairs, in a process of its own.

Called by bench/throughput.py (drjit's worker threads, once imported, compete with ours
in the same process). Usage: ``mitsuba_eval.py PAIRS.npz ALPHA REPEAT [OUT.npy]``:
PAIRS.npz holds l and v (n, 3); prints one JSON line {"seconds": median of REPEAT timed
evaluations after one untimed (which compiles the kernel)}; with OUT.npy also saves
f·cos θ_l (float64) there. GGX, α, η = 0, κ = 1 (the plugin's default material: F = 1).
"""
from __future__ import annotations

import json
import statistics
import sys
import time

import numpy as np


def main(argv: list[str]) -> int:
    pairs, alpha, repeat = argv[0], float(argv[1]), int(argv[2])
    import drjit as dr
    import mitsuba as mi
    mi.set_variant("llvm_ad_rgb")
    data = np.load(pairs)
    l, v = data["l"], data["v"]
    bsdf = mi.load_dict({"type": "roughconductor", "distribution": "ggx", "alpha": alpha})
    si = dr.zeros(mi.SurfaceInteraction3f)
    si.wi = mi.Vector3f(np.ascontiguousarray(v.T, dtype=np.float32))
    wo = mi.Vector3f(np.ascontiguousarray(l.T, dtype=np.float32))
    dr.eval(si.wi, wo)
    ctx = mi.BSDFContext()

    def run():
        value = bsdf.eval(ctx, si, wo)
        dr.eval(value)
        dr.sync_thread()
        return value

    value = run()               # compiles (or loads from drjit's cache)
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        run()
        times.append(time.perf_counter() - t0)
    if len(argv) > 3:
        np.save(argv[3], np.asarray(value[0], dtype=np.float64))   # the red channel (all alike)
    print(json.dumps({"seconds": statistics.median(times) if times else None}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
