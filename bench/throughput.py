"""Evaluation throughput: the full BRDF on 10⁶ random direction pairs.

GGX, height-correlated G2, Schlick (the page's default model), float64, through the
functions the API calls: BRDF.evaluate(l, v, ("f",)) (POST /eval, the lobe views, the
albedo quadrature's reference path) and app.quantities.evaluate (angles in degrees →
directions → BRDF.evaluate, as GET/POST /eval do). Side by side in one run:

* ``fast``        BRDF.evaluate with the compiled kernel (app/physics/fast.py), 2 threads
* ``fast_serial`` the same kernel on one thread (what each core does)
* ``numpy``       BRDF.evaluate on the reference numpy path (fast.disabled())
* ``quantities``  app.quantities.evaluate, degrees in (fast path)

Directions: uniform on the upper hemisphere (μ uniform in [0, 1], φ uniform).
"""
from __future__ import annotations

import numpy as np

import common  # first: puts the checkout on sys.path

from app import quantities
from app.model import make_spec
from app.physics import fast


def random_pairs(n: int, seed: int = 1):
    rng = np.random.default_rng(seed)
    mu = rng.random((2, n))
    phi = rng.random((2, n)) * 2.0 * np.pi
    s = np.sqrt(1.0 - mu * mu)
    d = np.stack([s * np.cos(phi), s * np.sin(phi), mu], axis=-1)
    theta_deg = np.degrees(np.arccos(mu))
    return d[0], d[1], theta_deg, np.degrees(phi)


def run(quick: bool = False) -> dict:
    n = 1_000_000
    repeat = 5 if quick else 15
    brdf = make_spec(ndf="ggx", g2="height_correlated", fresnel="schlick").brdf()
    l, v, theta, phi = random_pairs(n)
    have_fast = fast.spec_args(brdf) is not None

    def numpy_path():
        with fast.disabled():
            brdf.evaluate(l, v, ("f",))

    def serial():
        saved, fast.PARALLEL_MIN = fast.PARALLEL_MIN, 1 << 62
        try:
            brdf.evaluate(l, v, ("f",))
        finally:
            fast.PARALLEL_MIN = saved

    functions = {
        "fast": lambda: brdf.evaluate(l, v, ("f",)),
        "fast_serial": serial,
        "numpy": numpy_path,
        "quantities": lambda: quantities.evaluate(brdf, theta[0], phi[0], theta[1], phi[1], ("f",)),
    }
    if not have_fast:
        common.log("  (numba not installed or BRDF_FAST=0: 'fast' is the numpy path)")
    common.log(f"  {n:,} pairs, {repeat} interleaved rounds ...")
    cpu: dict = {}
    load0 = common.loadavg()
    times = common.interleaved(functions, repeat=repeat, warmup=1, cpu=cpu)
    out = {"throughput_pairs": n, "throughput_compiled": have_fast,
           "throughput_loadavg": [load0, common.loadavg()]}
    for name, ts in times.items():
        out[f"evals_per_s_{name}"] = n / common.median(ts)
        # per second of CPU of this process: what a core does when it gets to run
        out[f"evals_per_cpu_s_{name}"] = n / common.median(cpu[name])
    out["evals_per_s"] = out.pop("evals_per_s_fast")
    with fast.disabled():
        ref = brdf.evaluate(l, v, ("f",))["f"]
    got = brdf.evaluate(l, v, ("f",))["f"]
    finite = np.isfinite(ref) & (ref > 0)
    out["throughput_max_rel_diff"] = float(np.max(np.abs(got[finite] - ref[finite]) / ref[finite]))
    out["throughput_speedup"] = out["evals_per_s"] / out["evals_per_s_numpy"]
    return out


def report(r: dict) -> list[str]:
    return [
        f"evaluations/s (GGX, h-c G2, Schlick, float64, {r['throughput_pairs']:,} pairs; "
        f"load average {r['throughput_loadavg'][0]} → {r['throughput_loadavg'][1]})",
        "                                        wall clock    per CPU-second",
        f"  BRDF.evaluate, compiled, 2 threads : {r['evals_per_s'] / 1e6:8.1f} M/s  {r['evals_per_cpu_s_fast'] / 1e6:8.1f} M/s",
        f"  BRDF.evaluate, compiled, 1 thread  : {r['evals_per_s_fast_serial'] / 1e6:8.1f} M/s  "
        f"{r['evals_per_cpu_s_fast_serial'] / 1e6:8.1f} M/s",
        f"  BRDF.evaluate, numpy reference     : {r['evals_per_s_numpy'] / 1e6:8.1f} M/s  "
        f"{r['evals_per_cpu_s_numpy'] / 1e6:8.1f} M/s",
        f"  quantities.evaluate (degrees in)   : {r['evals_per_s_quantities'] / 1e6:8.1f} M/s  "
        f"{r['evals_per_cpu_s_quantities'] / 1e6:8.1f} M/s",
        f"  speed-up {r['throughput_speedup']:.1f}x; max relative difference to numpy "
        f"{r['throughput_max_rel_diff']:.1e}",
    ]


if __name__ == "__main__":
    result = run()
    print("\n".join(report(result)))
