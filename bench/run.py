"""Run every benchmark: ``python bench/run.py [--quick] [--json] [--only a,b] [--out FILE]``.

Benchmarks (each a module here with ``run(quick) -> dict`` and ``report(dict)``):

  throughput  full-BRDF evaluations per second, compiled and numpy, side by side
  accuracy    time to accuracy of E(μ): the 32×32 table at 1e-5, one E(μ) at 1e-6, MC
  scaling     lobe3d cost against grid size; albedo cost against tolerance
  latency     API p50/p95 per endpoint, warm, real uvicorn on 127.0.0.1
  slider      slider input → last panel redrawn, and a sustained drag, in headless Chromium

``--quick`` takes about a minute; the full run a few minutes. ``--json`` prints one JSON
object (one key per figure, plus "machine") on stdout and the readable report on
stderr. A benchmark that cannot run (no Chromium, say) is reported with its error under
``<name>_error`` and the others still run; the exit status is then 1.

Not here (slow, run on its own): bench/albedo_honesty.py, the albedo's error bound
against brute force at the hard points.
"""
from __future__ import annotations

import argparse
import datetime
import json
import subprocess
import sys
import time
import traceback

import common  # first: puts the checkout on sys.path

import accuracy
import latency
import scaling
import slider
import throughput

BENCHMARKS = {"throughput": throughput, "accuracy": accuracy, "scaling": scaling,
              "latency": latency, "slider": slider}


def git_commit() -> str | None:
    try:
        out = subprocess.run(["git", "rev-parse", "--short", "HEAD"], cwd=common.ROOT,
                             capture_output=True, text=True, timeout=5)
        dirty = subprocess.run(["git", "status", "--porcelain", "--untracked-files=no"],
                               cwd=common.ROOT, capture_output=True, text=True, timeout=5)
        return out.stdout.strip() + ("+dirty" if dirty.stdout.strip() else "") if out.returncode == 0 else None
    except (OSError, subprocess.SubprocessError):
        return None


def main(argv=None) -> int:
    ap = argparse.ArgumentParser(description="Run the BRDF explorer's benchmarks.")
    ap.add_argument("--quick", action="store_true", help="about a minute: fewer repeats and moves")
    ap.add_argument("--json", action="store_true", help="print a JSON summary on stdout")
    ap.add_argument("--only", help=f"comma-separated subset of {', '.join(BENCHMARKS)}")
    ap.add_argument("--out", help="also write the JSON summary to this file")
    args = ap.parse_args(argv)
    names = list(BENCHMARKS) if not args.only else [n.strip() for n in args.only.split(",")]
    unknown = [n for n in names if n not in BENCHMARKS]
    if unknown:
        ap.error(f"unknown benchmark(s): {', '.join(unknown)}")

    summary: dict = {"machine": common.machine(), "commit": git_commit(),
                     "date": datetime.datetime.now(datetime.timezone.utc).isoformat(timespec="seconds"),
                     "command": "python bench/run.py " + " ".join(argv if argv is not None else sys.argv[1:]),
                     "quick": args.quick}
    lines: list[str] = []
    m = summary["machine"]
    lines.append(f"machine: {m['nproc']} × {m['cpu']}; Python {m['python']}, numpy {m['numpy']}, "
                 f"scipy {m['scipy']}, numba {m['numba']}; load average {m['loadavg_at_start']}")
    failed = False
    for name in names:
        common.log(f"[{name}] ...")
        t0 = time.perf_counter()
        try:
            result = BENCHMARKS[name].run(quick=args.quick)
        except Exception as exc:    # report and go on: the other figures still count
            failed = True
            summary[f"{name}_error"] = f"{type(exc).__name__}: {exc}"
            common.log(traceback.format_exc())
            lines.append(f"{name}: FAILED — {summary[f'{name}_error']}")
            continue
        summary.update(result)
        summary[f"{name}_bench_seconds"] = round(time.perf_counter() - t0, 1)
        lines += BENCHMARKS[name].report(result)
    text = "\n".join(lines)
    if args.json:
        common.log(text)
        print(json.dumps(summary, indent=1, default=float))
    else:
        print(text)
    if args.out:
        with open(args.out, "w") as f:
            json.dump(summary, f, indent=1, default=float)
    return 1 if failed else 0


if __name__ == "__main__":
    raise SystemExit(main())
