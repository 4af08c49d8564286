"""What every benchmark shares: timing, statistics, the machine, a live server.

Benchmarks are not tests: they measure and report, they do not pass or fail. On a
shared machine absolute times move with the load, so each benchmark times the things
it compares in one run, interleaved (A, B, A, B, ...), and reports medians.
"""
from __future__ import annotations

import contextlib
import os
import platform
import statistics
import sys
import time
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
if str(ROOT) not in sys.path:       # `python bench/run.py` from a checkout, installed or not
    sys.path.insert(0, str(ROOT))


def log(*args) -> None:
    """Progress goes to stderr, so that --json leaves stdout to the summary."""
    print(*args, file=sys.stderr, flush=True)


def percentile(values, q: float) -> float:
    """The q-th percentile (0..100), linear between order statistics."""
    xs = sorted(values)
    if not xs:
        return float("nan")
    pos = (len(xs) - 1) * q / 100.0
    lo = int(pos)
    hi = min(lo + 1, len(xs) - 1)
    return xs[lo] + (xs[hi] - xs[lo]) * (pos - lo)


def median(values) -> float:
    return statistics.median(values)


def interleaved(functions: dict, repeat: int, warmup: int = 1,
                cpu: dict | None = None) -> dict[str, list[float]]:
    """Seconds per call of each function, run round-robin ``repeat`` times after
    ``warmup`` untimed rounds, so that a change of load hits all of them alike.

    If ``cpu`` is a dict, it receives the CPU seconds of this process per call (all its
    threads): what the work cost, whatever else the machine was doing meanwhile."""
    for _ in range(warmup):
        for fn in functions.values():
            fn()
    times = {name: [] for name in functions}
    if cpu is not None:
        cpu.update({name: [] for name in functions})
    for _ in range(repeat):
        for name, fn in functions.items():
            c0 = time.process_time()
            t0 = time.perf_counter()
            fn()
            times[name].append(time.perf_counter() - t0)
            if cpu is not None:
                cpu[name].append(time.process_time() - c0)
    return times


def loadavg() -> float | None:
    """The 1-minute load average (runnable processes; 2 means both cores busy)."""
    try:
        return round(os.getloadavg()[0], 2)
    except OSError:
        return None


def machine() -> dict:
    """The machine and software the numbers were measured on."""
    import numpy
    import scipy
    cpu = "unknown"
    try:
        for line in Path("/proc/cpuinfo").read_text().splitlines():
            if line.startswith("model name"):
                cpu = line.split(":", 1)[1].strip()
                break
    except OSError:
        pass
    try:
        import numba
        numba_version = numba.__version__
    except ImportError:
        numba_version = None
    try:
        load = os.getloadavg()
    except OSError:
        load = None
    return {
        "nproc": os.cpu_count(),
        "cpu": cpu,
        "python": platform.python_version(),
        "numpy": numpy.__version__,
        "scipy": scipy.__version__,
        "numba": numba_version,
        "platform": platform.platform(),
        "loadavg_at_start": load,
    }


from tests.live import free_port, running_server  # noqa: E402  (after the sys.path line)


@contextlib.contextmanager
def server(env: dict | None = None):
    """The real app in its own uvicorn process on a free port (tests/live.py, the one
    server-starting helper); yields its base URL and stops it (only it: by its pid)."""
    log_path = Path(os.environ.get("TMPDIR", "/tmp")) / f"brdf-bench-uvicorn-{os.getpid()}.log"
    with running_server(env=env, log_path=log_path) as (url, _):
        yield url
