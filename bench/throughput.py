"""Evaluation throughput: the full BRDF on 10⁶ random direction pairs.

GGX, height-correlated G2, Schlick (the page's default model), float64, through the
functions the API calls: BRDF.evaluate(l, v, ("f",)) (POST /eval, the lobe views, the
albedo quadrature's reference path) and app.quantities.evaluate (angles in degrees →
directions → BRDF.evaluate, as GET/POST /eval do). Side by side in one run:

* ``fast``        app.kernels.f: the model's compiled loop (app/kernels), one block per core
* ``fast_serial`` the same loop on one thread (what each core does)
* ``numpy``       BRDF.evaluate, the reference numpy path
* ``quantities``  app.quantities.evaluate, degrees in: the compiled loop that builds the
                  directions itself (f_deg_loop, app/kernels/compose.py), one block per core
* ``mitsuba``     Mitsuba 3's LLVM backend (optional, float32) on the same pairs, timed in a
                  process of its own (bench/mitsuba_eval.py; drjit's worker threads in this
                  process halved our 2-thread numbers), in rounds of its own before ours.
                  ``roughconductor``, GGX, α as ours, its default material ("none": F = 1;
                  the report checks the values against ours to float32 precision), its separable
                  Smith G2 = G1(l) G1(v); it returns f·cos θ_l. Timed against our compiled
                  loop on the same model (GGX, smith, separable, fresnel=none; float64) as
                  ``fast_mitsuba_model``. Both sides: the same 10⁶ direction pairs already in
                  memory (not generated in the timing), the outputs allocated in each call
                  (ours np.empty, Mitsuba its JIT's result), 2 threads each (drjit's pool =
                  the core count, ours WORKERS), median of the timed calls.
                  Set up:  pip install mitsuba  (3.9.1 here), and Debian's libLLVM 19 unpacked:
                  ``cd /tmp && apt-get download libllvm19 && dpkg-deb -x libllvm19_*.deb /tmp/llvm19``,
                  then run with ``DRJIT_LIBLLVM_PATH=/tmp/llvm19/usr/lib/x86_64-linux-gnu/libLLVM.so.19.1``.
                  Without it the report says "not measured" and why.
* ``fast32_mitsuba_model`` the float32 loop (app/kernels/float32.py, on explicit request
                  only: generated from the same formulas, 8 lanes a step) on the same model
                  and pairs, given as float32 arrays made before the timing (as Mitsuba's
                  are): the report prints both ratios, ours float64 / Mitsuba and ours
                  float32 / Mitsuba, and the float32 loop's largest relative difference to
                  the float64 numpy path on these pairs (``float32_max_rel_diff``), beside
                  its stated bound (app.kernels.float32.REL_ERROR_K / (α (μ_l + μ_v)), at
                  the pairs' smallest μ_l + μ_v).

Run it as installed by the README's first command (numba is a regular dependency); the
compiled loop is loaded (or compiled) before the timings.

Directions: uniform on the upper hemisphere (μ uniform in [0, 1], φ uniform).
"""
from __future__ import annotations

import contextlib
import subprocess
import sys
import tempfile
from pathlib import Path

import numpy as np

import common  # first: puts the checkout on sys.path

from app import kernels, quantities
from app.kernels import float32 as float32_module
from app.kernels import kernel as kernel_module
from app.model import make_spec


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
    have_fast = kernels.compile_now(brdf, "f") is not None

    def numpy_path():
        brdf.evaluate(l, v, ("f",))

    def serial():
        saved, kernel_module.PARALLEL_MIN = kernel_module.PARALLEL_MIN, 1 << 62
        try:
            kernels.f(brdf, l, v)
        finally:
            kernel_module.PARALLEL_MIN = saved

    same = make_spec(ndf="ggx", masking="smith", g2="separable", fresnel="none").brdf()
    kernels.compile_now(same, "f")
    functions = {
        "fast": lambda: kernels.f(brdf, l, v),
        "fast_serial": serial,
        "quantities": lambda: quantities.evaluate(brdf, theta[0], phi[0], theta[1], phi[1], ("f",)),
        "fast_mitsuba_model": lambda: kernels.f(same, l, v),
    }
    if have_fast:
        float32_module.kernel(same)                    # compiled (or loaded) before the timings
        l32, v32 = l.astype(np.float32), v.astype(np.float32)
        functions["fast32_mitsuba_model"] = lambda: float32_module.f(same, l32, v32)
    if not have_fast:
        common.log("  (numba not installed or BRDF_FAST=0: 'fast' is the numpy path)")
    common.log(f"  {n:,} pairs, {repeat} interleaved rounds ...")
    cpu: dict = {}
    load0 = common.loadavg()
    # Mitsuba's calls in rounds of their own, before ours, and its process ended: interleaved,
    # each call of ours followed a wait for drjit's threads to go quiet (≥ 20 ms of idle), and
    # after such a pause this VM often ran our two threads on one core for the whole call
    # (1.0 core busy, 91-99 M/s against 180-200 back to back: /proc/stat showed the other
    # core idle, Mitsuba's process 0 ms of CPU), so the ratio measured the scheduler
    times = {}
    with mitsuba_process(l, v, same.ndf.alpha_x) as (mitsuba, why):
        if mitsuba is not None:
            times.update(common.interleaved({"mitsuba": mitsuba}, repeat=repeat, warmup=1))
    times.update(common.interleaved(functions, repeat=repeat, warmup=1, cpu=cpu))
    # the numpy reference in rounds of its own: interleaved with the others, the memory its
    # temporaries freed (~5 800 page faults a call) left whichever function came next to fault
    # its output in afresh (quantities: ~900 page faults a call, 14 ms of CPU against 12 ms)
    times.update(common.interleaved({"numpy": numpy_path}, repeat=repeat, warmup=1, cpu=cpu))
    out = {"throughput_pairs": n, "throughput_compiled": have_fast,
           "throughput_loadavg": [load0, common.loadavg()]}
    for name, ts in times.items():
        out[f"evals_per_s_{name}"] = n / common.median(ts)
        # per second of CPU of this process: what a core does when it gets to run
        # (not for Mitsuba, whose CPU time is another process's)
        if name != "mitsuba":
            out[f"evals_per_cpu_s_{name}"] = n / common.median(cpu[name])
    out["evals_per_s"] = out.pop("evals_per_s_fast")
    ref = brdf.evaluate(l, v, ("f",))["f"]
    got = kernels.f(brdf, l, v)
    finite = np.isfinite(ref) & (ref > 0)
    out["throughput_max_rel_diff"] = float(np.max(np.abs(got[finite] - ref[finite]) / ref[finite]))
    out["throughput_speedup"] = out["evals_per_s"] / out["evals_per_s_numpy"]
    out["quantities_over_fast"] = out["evals_per_s_quantities"] / out["evals_per_s"]
    if have_fast:
        ref_same = same.evaluate(l, v, ("f",))["f"]
        got32 = float32_module.f(same, l, v).astype(np.float64)
        ok = np.isfinite(ref_same) & (ref_same > 0)
        out["float32_max_rel_diff"] = float(np.max(np.abs(got32[ok] - ref_same[ok]) / ref_same[ok]))
        mu_sum = (l[:, 2] + v[:, 2])[ok]
        out["float32_bound_at_min_mu"] = float(float32_module.rel_error_bound(
            same.ndf.alpha_x, same.ndf.alpha_y, mu_sum.min()))
        out["float32_bound_check"] = bool(np.all(np.abs(got32[ok] - ref_same[ok]) <= float32_module.rel_error_bound(
            same.ndf.alpha_x, same.ndf.alpha_y, mu_sum) * ref_same[ok]))
    if "mitsuba" in times:
        out["ours_over_mitsuba"] = out["evals_per_s_fast_mitsuba_model"] / out["evals_per_s_mitsuba"]
        if "evals_per_s_fast32_mitsuba_model" in out:
            out["ours32_over_mitsuba"] = out["evals_per_s_fast32_mitsuba_model"] / out["evals_per_s_mitsuba"]
        out["mitsuba_max_rel_diff"] = mitsuba_check(same, l, v)
    else:
        out["mitsuba_not_measured"] = why
    out.update(albedo_latency(brdf, repeat=repeat))
    return out


MITSUBA_SCRIPT = Path(__file__).with_name("mitsuba_eval.py")


@contextlib.contextmanager
def mitsuba_process(l, v, alpha: float):
    """(a function that has Mitsuba's roughconductor evaluate the pairs once, in a process
    of its own kept waiting between calls (bench/mitsuba_eval.py serve), and returns when it
    is done, its process id as its ``pid``; None) — or (None, why not). Timed by
    ``common.interleaved`` among our own functions; its pipe round trip (~0.1 ms) is in the
    time. Mitsuba is optional, never a dependency."""
    with tempfile.TemporaryDirectory() as tmp:
        pairs = Path(tmp) / "pairs.npz"
        np.savez(pairs, l=l, v=v)
        proc = subprocess.Popen([sys.executable, str(MITSUBA_SCRIPT), str(pairs), repr(alpha), "serve"],
                                stdin=subprocess.PIPE, stdout=subprocess.PIPE, stderr=subprocess.PIPE, text=True)
        try:
            first = proc.stdout.readline().strip()
            if first != "ready":
                err = proc.communicate(timeout=60)[1].strip().splitlines()
                yield None, err[-1] if err else f"exit status {proc.returncode}"
                return

            def run():
                proc.stdin.write("run\n")
                proc.stdin.flush()
                float(proc.stdout.readline())
            run.pid = proc.pid
            yield run, None
        finally:
            if proc.poll() is None:
                proc.stdin.close()
                proc.wait(timeout=60)


def mitsuba_check(brdf, l, v, n: int = 2000) -> float | None:
    """Largest relative difference of Mitsuba's f·cos θ_l / cos θ_l to ours on the first
    ``n`` pairs away from grazing (float32 against float64): that the two evaluate the
    same BSDF."""
    with tempfile.TemporaryDirectory() as tmp:
        pairs = Path(tmp) / "pairs.npz"
        np.savez(pairs, l=l[:n], v=v[:n])
        run = subprocess.run([sys.executable, str(MITSUBA_SCRIPT), str(pairs), repr(brdf.ndf.alpha_x),
                              "0", str(Path(tmp) / "f.npy")], capture_output=True, text=True, timeout=600)
        if run.returncode != 0:
            return None
        theirs = np.load(Path(tmp) / "f.npy")
    ours = kernels.f(brdf, l[:n], v[:n]) * l[:n, 2]
    ok = (l[:n, 2] > 0.05) & (v[:n, 2] > 0.05) & (ours > 0)
    return float(np.max(np.abs(theirs[ok] - ours[ok]) / ours[ok]))


def albedo_latency(brdf, repeat: int) -> dict:
    """GET /albedo's computation at the page's n = 17 (E at 17 cosines and E_avg, tol
    1e-5, quadrature), compiled and numpy, interleaved: median and p90 in ms."""
    mu = np.linspace(0.0, 1.0, 17)
    # the albedo's own loops: kernels compile a model's parts by use, and the timings
    # above asked for its f loops only (without this line "compiled" timed numpy)
    kernels.compile_now(brdf, "albedo")

    def compiled():
        quantities.albedo_curve(brdf, mu, 0.0, 1e-5)

    def numpy_path():
        with kernels.disabled():
            quantities.albedo_curve(brdf, mu, 0.0, 1e-5)

    cpu: dict = {}
    times = common.interleaved({"compiled": compiled, "numpy": numpy_path},
                               repeat=max(repeat, 20), warmup=1, cpu=cpu)
    out = {f"albedo17_{k}_ms_{stat}": 1e3 * f(ts) for k, ts in times.items()
           for stat, f in (("p50", common.median), ("p90", lambda x: common.percentile(x, 90)))}
    out.update({f"albedo17_{k}_cpu_ms_p50": 1e3 * common.median(ts) for k, ts in cpu.items()})
    return out


def report(r: dict) -> list[str]:
    return [
        f"evaluations/s (GGX, h-c G2, Schlick, float64, {r['throughput_pairs']:,} pairs; "
        f"load average {r['throughput_loadavg'][0]} → {r['throughput_loadavg'][1]})",
        "                                        wall clock    per CPU-second",
        f"  kernels.f, compiled, 2 threads     : {r['evals_per_s'] / 1e6:8.1f} M/s  {r['evals_per_cpu_s_fast'] / 1e6:8.1f} M/s",
        f"  kernels.f, compiled, 1 thread      : {r['evals_per_s_fast_serial'] / 1e6:8.1f} M/s  "
        f"{r['evals_per_cpu_s_fast_serial'] / 1e6:8.1f} M/s",
        f"  BRDF.evaluate, numpy reference     : {r['evals_per_s_numpy'] / 1e6:8.1f} M/s  "
        f"{r['evals_per_cpu_s_numpy'] / 1e6:8.1f} M/s",
        f"  quantities.evaluate (degrees in)   : {r['evals_per_s_quantities'] / 1e6:8.1f} M/s  "
        f"{r['evals_per_cpu_s_quantities'] / 1e6:8.1f} M/s",
        f"  quantities / kernels.f             : {r['quantities_over_fast']:8.2f}",
        (f"  GGX separable F=1: ours {r['evals_per_s_fast_mitsuba_model'] / 1e6:.1f} M/s (float64), Mitsuba 3 LLVM "
         f"{r['evals_per_s_mitsuba'] / 1e6:.1f} M/s (float32, own process): ratio {r['ours_over_mitsuba']:.2f}; "
         f"max rel. difference {r['mitsuba_max_rel_diff'] if r['mitsuba_max_rel_diff'] is not None else float('nan'):.1e}"
         if "ours_over_mitsuba" in r else f"  Mitsuba 3: not measured ({r['mitsuba_not_measured']})"),
        (f"  GGX separable F=1, float32 loop: {r['evals_per_s_fast32_mitsuba_model'] / 1e6:.1f} M/s; "
         f"ratio to Mitsuba: float64 {r['ours_over_mitsuba']:.2f}, float32 {r['ours32_over_mitsuba']:.2f}; "
         f"float32 max rel. difference to float64 {r['float32_max_rel_diff']:.1e} (stated bound "
         f"{r['float32_bound_at_min_mu']:.1e} at the pairs' smallest mu_l + mu_v; held pair by pair: "
         f"{r['float32_bound_check']})"
         if "ours32_over_mitsuba" in r else "  float32 loop / Mitsuba: not measured"),
        f"  speed-up {r['throughput_speedup']:.1f}x; max relative difference to numpy "
        f"{r['throughput_max_rel_diff']:.1e}",
        f"albedo, n = 17 + E_avg, tol 1e-5: compiled p50 {r['albedo17_compiled_ms_p50']:.1f} ms "
        f"(p90 {r['albedo17_compiled_ms_p90']:.1f}), numpy p50 {r['albedo17_numpy_ms_p50']:.1f} ms "
        f"(p90 {r['albedo17_numpy_ms_p90']:.1f}); CPU time p50: compiled "
        f"{r['albedo17_compiled_cpu_ms_p50']:.1f} ms, numpy {r['albedo17_numpy_cpu_ms_p50']:.1f} ms",
    ]


if __name__ == "__main__":
    result = run()
    print("\n".join(report(result)))
