"""Compile the fast path before any request is timed.

numba compiles a loop on its first call (or loads it from its on-disk cache, which a
fresh clone or a new version of the source does not have yet). Measured on a fresh clone
(2 cores): the six loops of app/physics/fast.py and app/integrate/albedo_kernel.py take
6.7 s to compile one by one on an idle machine, 11-12 s at a server's start with other
work running, 0.3 s to load from the cache. Left to the first request, that time
counts against the request's budget (BRDF_MAX_SECONDS), and worse, against every
prediction made from it: the advice and the tables time their first row and predict the
rest from it, so a row that included the compile predicted a request ten times too slow
and cut it (a fresh process answered the advice incomplete: CI, stop 9).

So the server compiles at start-up (the app's lifespan, before it accepts a connection),
and the middleware makes sure of it before it opens a request's budget — for an app
served without its lifespan (the test client) the first request waits for the compile,
outside its budget. Without numba (or with BRDF_FAST=0) there is nothing to do.
"""
from __future__ import annotations

import threading
import time

from .integrate import albedo_kernel
from .physics import fast

_done = threading.Event()
_lock = threading.Lock()


def done() -> bool:
    return _done.is_set()


def warm_up() -> float:
    """Compile every loop once per process; the seconds it took (0 when already done)."""
    if _done.is_set():
        return 0.0
    with _lock:
        if _done.is_set():
            return 0.0
        t0 = time.perf_counter()
        if fast.AVAILABLE:
            fast.compile_loops()
            albedo_kernel.compile_loops()
        _done.set()
        return time.perf_counter() - t0
