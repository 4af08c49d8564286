"""Render time of the environment-lit sphere (GET /api/v1/figures/sphere_env's work):
a 256² sphere (51 468 pixels on it) for a few models and environments, interleaved,
medians of wall-clock and CPU seconds of this process, with the samples per pixel and
the noise each render states. The compiled loops are warmed before timing (the server
compiles them in the background at start-up); the principled BRDF runs on numpy.

    python bench/sphere_env.py [n] [samples] [repeat]     e.g.  python bench/sphere_env.py 256 16 5
"""
from __future__ import annotations

import sys

sys.path.insert(0, ".")
from app import kernels  # noqa: E402
from app.environment.render import render, render_point  # noqa: E402
from app.model import make_spec  # noqa: E402
from bench.common import interleaved, loadavg, median  # noqa: E402

CASES = {
    "ggx α=0.3 + Lambert kd=0.5, studio": (dict(alpha=0.3, kd=0.5), "studio"),
    "ggx α=0.5 F=1 Kulla-Conty, uniform (furnace)": (dict(alpha=0.5, fresnel="none", multiscatter="kulla_conty"), "uniform"),
    "burley diffuse kd=0.8, overcast": (dict(alpha=0.2, kd=0.8, diffuse="burley"), "overcast"),
    "principled (clearcoat 1, sheen 0.5), sunset": (dict(model="principled", clearcoat=1.0, sheen=0.5), "sunset"),
    "principled metallic=1, studio": (dict(model="principled", metallic=1.0, roughness=0.3), "studio"),
}


def main() -> None:
    n = int(sys.argv[1]) if len(sys.argv) > 1 else 256
    samples = int(sys.argv[2]) if len(sys.argv) > 2 else 16
    repeat = int(sys.argv[3]) if len(sys.argv) > 3 else 5
    brdfs = {name: make_spec(**model).brdf() for name, (model, _) in CASES.items()}
    for brdf in brdfs.values():
        kernels.compile_now(brdf)
    reports = {}

    def job(name):
        def run():
            reports[name] = render(brdfs[name], CASES[name][1], 40.0, 135.0, n, samples)
        return run

    functions = {name: job(name) for name in CASES}
    functions["point light (ggx α=0.3)"] = lambda: render_point(brdfs[next(iter(CASES))], 40.0, 135.0, n)
    print(f"load before: {loadavg()}; {n}² sphere, {samples} samples/pixel, {repeat} rounds (medians)")
    cpu: dict = {}
    times = interleaved(functions, repeat, warmup=1, cpu=cpu)
    print(f"{'case':<48} {'wall [s]':>9} {'cpu [s]':>8} {'noise (rel.)':>13} {'strategies env/cos/vndf':>24}")
    for name in functions:
        r = reports.get(name)
        noise = f"{100 * r['noise']['relative']:.1f} %" if r else "—"
        s = r["samples"] if r else None
        split = f"{s['environment']}/{s['cosine']}/{s['visible_normals']}" if s else "—"
        print(f"{name:<48} {median(times[name]):>9.3f} {median(cpu[name]):>8.3f} {noise:>13} {split:>24}")
    print(f"load after: {loadavg()}")


if __name__ == "__main__":
    main()
