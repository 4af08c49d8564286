"""Fits to a whole MERL file: seconds, evaluations and recovered parameters per NDF.

The file is written from a known model (GGX α = 0.2, F0 = 0.9 in red, kd = 0.1;
tests/datasets/known.py), uploaded as the API reads it, and fitted on its red channel
from a far start (α = 0.5, F0 = 0.5, kd = 0.5) with α, F0 and kd free, by every NDF of
the registry, on the default subset (app/fit/run.py: MAX_POINTS fixed-seed random
measured cells of the 1.1 M). Interleaved rounds (ggx, beckmann, …, ggx, …), medians;
wall and CPU seconds. Also: reading and summarising the file, and the MERL export.

    python bench/fit.py [--quick] [--measure log|relative|cosine]
"""
from __future__ import annotations

import argparse
import time

import common  # first: puts the checkout on sys.path

from app.datasets import formats, summary, tabulate
from app.fit import run as fitting
from app.model import make_spec
from app.physics.ndf import NDFS
from tests.datasets import known

START = {"alpha": 0.5, "f0": 0.5, "kd": 0.5}
FREE = ["alpha", "f0", "kd"]


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--quick", action="store_true", help="one round instead of three")
    parser.add_argument("--measure", default="log", choices=["log", "relative", "cosine"])
    args = parser.parse_args()
    content = known.merl_bytes()
    data = formats.load(content)
    results = {}

    def fit(ndf):
        def once():
            results[ndf] = fitting.fit(data, {**START, "ndf": ndf}, FREE, args.measure, "r", seconds=60.0)
        return once
    functions = {"read": lambda: formats.load(content), "summary": lambda: summary.summarize(data),
                 "export": lambda: tabulate.merl_bytes(make_spec(**known.model("r")).brdf()),
                 **{ndf: fit(ndf) for ndf in NDFS}}
    cpu: dict = {}
    times = common.interleaved(functions, repeat=1 if args.quick else 3, warmup=0 if args.quick else 1,
                               cpu=cpu)
    print(f"machine: {common.machine()}  load before: {common.loadavg()}")
    print(f"measure: {args.measure}; points: {results['ggx']['points']['note']}")
    print(f"{'what':>12} {'wall s':>8} {'cpu s':>7} {'evals':>6} {'residual':>10}  params ± stderr")
    for name, values in times.items():
        line = f"{name:>12} {common.median(values):8.2f} {common.median(cpu[name]):7.2f}"
        if name in results:
            r = results[name]
            stderr = r["stderr"] or {}
            params = ", ".join(f"{k}={v:.4f}±{stderr.get(k, float('nan')):.1e}" for k, v in r["params"].items())
            line += f" {r['evaluations']:6d} {r['residual']:10.2e}  {params}"
            if not r["converged"]:
                line += f"  ({r['message']})"
        print(line)
    print(f"load after: {common.loadavg()}  ({time.strftime('%H:%M')})")


if __name__ == "__main__":
    main()
