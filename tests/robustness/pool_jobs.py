"""Jobs for the heavy-pool tests (tests/robustness/test_heavy_pool.py), in a module that
imports only the standard library: a spawned worker imports the module a job lives in
before it runs the job, and importing the test module (pytest, pydantic, the app) took
past a 2 s budget under the whole suite's load, cutting a 0.1 s job."""
from __future__ import annotations

import time


def rss() -> float:
    """This process's resident memory, MB."""
    with open("/proc/self/statm") as f:
        return int(f.read().split()[1]) * 4096 / 2**20


def spin(seconds: float) -> float:
    """Pure-Python CPU work (holds the GIL of whichever process runs it)."""
    end, x = time.perf_counter() + seconds, 0.0
    while time.perf_counter() < end:
        x += 1.0
    return seconds


def cheap() -> None:
    """A slider request's share of Python work: ~2 ms."""
    sum(i * i for i in range(20_000))


def square(x: int) -> int:
    return x * x


def resident_growth_after_large_arrays() -> float:
    """MB of resident memory left after six threads made and freed arrays of 4-52 MB
    (what large jobs do), as tests/robustness/test_server.py measures a server worker."""
    import threading

    import numpy as np

    def work(k):
        for i in range(30):
            a = np.ones((1 + (i * 7 + k) % 13) * 500_000)
            b = a * 2
            del a, b

    base = rss()
    threads = [threading.Thread(target=work, args=(k,)) for k in range(6)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return rss() - base


def resident_step_of_compiled_work() -> float:
    """MB of resident memory that evaluating the default model by its compiled loops adds
    to this process: numba and LLVM come with the first such job unless the process
    loaded them as it started."""
    import numpy as np

    from app import kernels
    from app.model import make_spec
    before = rss()
    brdf = make_spec().brdf()
    kernels.compile_now(brdf, "f")
    l = np.tile([0.0, 0.6, 0.8], (10_000, 1))
    kernels.f(brdf, l, l)
    return rss() - before


def nap(seconds: float) -> float:
    """A job that ends by itself after ``seconds`` (sleeping, not checking any budget)."""
    time.sleep(seconds)
    return seconds


def pid() -> int:
    """The process that ran this job."""
    import os
    return os.getpid()
