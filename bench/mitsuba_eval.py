"""Mitsuba 3's roughconductor (LLVM backend) on direction pairs, in a process of its own.

Called by bench/throughput.py (drjit's worker threads, once imported, compete with ours
in the same process). With REPEAT = serve it evaluates once (compiling), prints "ready",
then evaluates once per line read from stdin and prints the seconds it took: the
benchmark times it interleaved with its own rounds. Otherwise
``mitsuba_eval.py PAIRS.npz ALPHA REPEAT [OUT.npy]``:
PAIRS.npz holds l and v (n, 3); prints one JSON line {"seconds": median of REPEAT timed
evaluations after one untimed (which compiles the kernel), "times": each of them}; with OUT.npy also saves
f·cos θ_l (float64) there. GGX, α, the plugin's default material ("none": F = 1).
"""
from __future__ import annotations

import json
import statistics
import sys
import time

import numpy as np


def main(argv: list[str]) -> int:
    pairs, alpha = argv[0], float(argv[1])
    repeat = 0 if argv[2] == "serve" else int(argv[2])
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
    if argv[2] == "serve":
        print("ready", flush=True)
        for _ in sys.stdin:
            t0 = time.perf_counter()
            run()
            print(time.perf_counter() - t0, flush=True)
        return 0
    times = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        run()
        times.append(time.perf_counter() - t0)
    if len(argv) > 3:
        np.save(argv[3], np.asarray(value[0], dtype=np.float64))   # the red channel (all alike)
    print(json.dumps({"seconds": statistics.median(times) if times else None, "times": times}))
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))
