"""Render time of the environment-lit sphere (GET /api/v1/figures/sphere_env's work):
a 256² sphere (51 468 pixels on it) for a few models and environments, interleaved,
medians of wall-clock and CPU seconds of the rendering process (all its threads), with
the samples per pixel and the noise each render states. The compiled loops are warmed
before timing (the server compiles them in the background at start-up).

    python bench/sphere_env.py [n] [samples] [repeat]     e.g.  python bench/sphere_env.py 256 16 5
    python bench/sphere_env.py 256 16 5 --compare DIR     DIR: another checkout (e.g. from
        `git archive`): each tree renders in a process of its own, the two alternating
        round by round, and the table puts them side by side
    python bench/sphere_env.py --accuracy [DIR]           the error actually made: each case
        on a 64² sphere at 16 samples/pixel (4 seeds) against the same tree's render at
        1024 (a 32 × 32 grid per strategy and pixel), per-pixel RMS and mean error over
        the mean radiance, beside the noise the render states
"""
from __future__ import annotations

import json
import os
import subprocess
import sys
import time
from pathlib import Path

CASES = {
    "ggx α=0.3 + Lambert kd=0.5, studio": (dict(alpha=0.3, kd=0.5), "studio"),
    "ggx α=0.5 F=1 Kulla-Conty, uniform (furnace)": (dict(alpha=0.5, fresnel="none", multiscatter="kulla_conty"), "uniform"),
    "burley diffuse kd=0.8, overcast": (dict(alpha=0.2, kd=0.8, diffuse="burley"), "overcast"),
    "principled defaults, studio": (dict(model="principled"), "studio"),
    "principled (clearcoat 1, sheen 0.5), sunset": (dict(model="principled", clearcoat=1.0, sheen=0.5), "sunset"),
    "principled metallic=1, studio": (dict(model="principled", metallic=1.0, roughness=0.3), "studio"),
    "principled Kulla-Conty, studio": (dict(model="principled", principled_multiscatter="kulla_conty"), "studio"),
}
POINT = "point light (ggx α=0.3)"
ROOT = Path(__file__).resolve().parents[1]


def _renderers():
    """(render(brdf, environment, θ, φ, n, samples, seed=), render_point(brdf, θ, φ, n)) of
    the tree on sys.path: its one lit_sphere, or a tree from before it's two functions."""
    try:
        from app.environment.sphere import POINT_IRRADIANCE, environment_lighting, lit_sphere, point_light
    except ImportError:
        from app.environment.render import render, render_point
        return render, render_point
    return (lambda b, env, t, p, n, s, seed=0: lit_sphere(b, environment_lighting(env, t, p), n, samples=s, seed=seed),
            lambda b, t, p, n: lit_sphere(b, point_light(t, p, (POINT_IRRADIANCE,) * 3), n))


def _renderer(root: Path, n: int, samples: int):
    """{case: a function rendering it once, returning its report}, from the tree at root."""
    sys.path.insert(0, str(root))
    import app
    assert Path(app.__file__).resolve().is_relative_to(root), app.__file__
    from app import kernels
    from app.model import make_spec
    render, render_point = _renderers()
    try:
        from app.environment.evaluate import prepare
    except ImportError:                       # a tree from before it: the model's own loops
        prepare = kernels.compile_now
    brdfs = {name: make_spec(**model).brdf() for name, (model, _) in CASES.items()}
    for brdf in brdfs.values():
        kernels.compile_now(brdf)
        prepare(brdf)
    jobs = {name: (lambda name=name: render(brdfs[name], CASES[name][1], 40.0, 135.0, n, samples))
            for name in CASES}
    jobs[POINT] = lambda: render_point(brdfs[next(iter(CASES))], 40.0, 135.0, n)
    return jobs


def _round(jobs) -> dict:
    out = {}
    for name, job in jobs.items():
        c0, t0 = time.process_time(), time.perf_counter()
        r = job()
        wall, cpu = time.perf_counter() - t0, time.process_time() - c0
        s = r["samples"]
        out[name] = {"wall": wall, "cpu": cpu,
                     "noise": r["noise"]["relative"] if r["noise"] else None,
                     "split": f"{s['environment']}/{s['cosine']}/{s['visible_normals']}" if s else "—"}
    return out


def child(root: str, n: int, samples: int) -> None:
    """One tree's renders, a round per line 'round' on stdin, one JSON line back each."""
    jobs = _renderer(Path(root), n, samples)
    _round(jobs)                                       # warm-up
    print("ready", flush=True)
    for line in sys.stdin:
        if line.strip() != "round":
            break
        print(json.dumps(_round(jobs)), flush=True)


def accuracy(root: Path, n: int = 64, samples: int = 16, seeds: int = 4, ref_samples: int = 1024) -> None:
    import numpy as np
    sys.path.insert(0, str(root))
    from app.model import make_spec
    render, _ = _renderers()
    lum = np.array([0.2126, 0.7152, 0.0722])
    print(f"{root}: {n}² sphere, {samples} samples/pixel × {seeds} seeds against {ref_samples}")
    print(f"{'case':<46}{'RMS error':>11}{'mean error':>12}{'stated':>9}")
    for name, (model, environment) in CASES.items():
        brdf = make_spec(**model).brdf()
        ref = render(brdf, environment, 40.0, 135.0, n, ref_samples, seed=99)["radiance"] @ lum
        on = ~np.isnan(ref)
        mean = ref[on].mean()
        rms, bias, stated = [], [], []
        for seed in range(seeds):
            r = render(brdf, environment, 40.0, 135.0, n, samples, seed=seed)
            d = (r["radiance"] @ lum)[on] - ref[on]
            rms.append(np.sqrt(np.mean(d * d)) / mean)
            bias.append(d.mean() / mean)
            stated.append(r["noise"]["relative"])
        print(f"{name:<46}{100 * np.mean(rms):>10.1f}%{100 * np.mean(bias):>+11.2f}%{100 * np.mean(stated):>8.1f}%")


def main() -> None:
    args = [a for a in sys.argv[1:] if not a.startswith("--")]
    if "--accuracy" in sys.argv:
        accuracy(Path(args[0]).resolve() if args else ROOT)
        return
    if "--child" in sys.argv:
        child(args[0], int(args[1]), int(args[2]))
        return
    trees = {"now": ROOT}
    if "--compare" in sys.argv:
        before = sys.argv[sys.argv.index("--compare") + 1]
        trees = {"before": Path(before).resolve(), "now": ROOT}
        args.remove(before)
    n = int(args[0]) if len(args) > 0 else 256
    samples = int(args[1]) if len(args) > 1 else 16
    repeat = int(args[2]) if len(args) > 2 else 5
    # both trees load the compiled loops from the user's one cache (same formulas, same files)
    env = {**os.environ, "PYTHONPATH": ""}
    procs = {k: subprocess.Popen([sys.executable, __file__, "--child", str(root), str(n), str(samples)],
                                 stdin=subprocess.PIPE, stdout=subprocess.PIPE, text=True, env=env, cwd=root)
             for k, root in trees.items()}
    for p in procs.values():
        assert p.stdout.readline().strip() == "ready"
    print(f"load before: {os.getloadavg()[0]:.2f}; {n}² sphere, {samples} samples/pixel, "
          f"{repeat} rounds (medians), trees: {', '.join(f'{k}={v}' for k, v in trees.items())}")
    rounds = {k: [] for k in trees}
    for r in range(repeat):
        for k in (list(trees) if r % 2 == 0 else list(trees)[::-1]):     # alternate who goes first
            procs[k].stdin.write("round\n")
            procs[k].stdin.flush()
            rounds[k].append(json.loads(procs[k].stdout.readline()))
    for p in procs.values():
        p.stdin.close()
        p.wait()

    def med(k, name, q):
        return sorted(x[name][q] for x in rounds[k])[len(rounds[k]) // 2]

    head = "".join(f"{k + ' wall':>12}{k + ' cpu':>11}" for k in trees)
    print(f"{'case':<46}{head}{'noise (rel.)':>14}{'env/cos/vndf':>14}")
    for name in [*CASES, POINT]:
        cols = "".join(f"{med(k, name, 'wall'):>12.3f}{med(k, name, 'cpu'):>11.3f}" for k in trees)
        noise = " / ".join(f"{100 * rounds[k][0][name]['noise']:.1f}" if rounds[k][0][name]["noise"] is not None
                           else "—" for k in trees)
        split = " / ".join(rounds[k][0][name]["split"] for k in trees)
        print(f"{name:<46}{cols}{noise + ' %':>14}{split:>14}")
    print(f"load after: {os.getloadavg()[0]:.2f}")


if __name__ == "__main__":
    main()
