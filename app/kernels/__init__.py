"""Compiled loops generated from the physics' own scalar formulas.

``lookup(brdf, part)`` gives the compiled :class:`~.kernel.Kernel` of a model for one use
(``part``: "f" to evaluate it, "albedo" to integrate it; kernel.PARTS), or None — when
numba is absent or switched off (BRDF_FAST=0), when a component has no scalar formula,
or while those loops are still being compiled. Until then the caller takes the numpy path
(BRDF.evaluate knows nothing of this package) inside :func:`numpy_path`, which counts the
CPU seconds it spends; once a model part's numpy work reaches RENT_SECONDS it is queued
(ahead of what was queued earlier: what is in use now compiles next) and compiled by one
background thread (with a compiler process, so that compiling does not hold this
process's GIL). Rent or buy: a compile costs ~1.5-3 s of CPU a part, so a model used in
passing (a script's sweep over models, a fuzzer, a few figures) never pays one, and a
model in use (a drag, a table build) pays it after a fraction of its price in numpy work.
Only the part in use compiles: a table build (albedo rows) never waits for the loops
that evaluate f. :func:`start` queues the models the server
expects, :func:`compile_now` compiles in the calling thread (tests, benchmarks, the CLI).
The log says which path answered: one line when a model's loops are ready (compiled, or
loaded from numba's cache, and how long it took), one when a model was first answered
by numpy because its loops were not ready.
"""
from __future__ import annotations

import contextlib
import importlib.util
import logging
import threading
import time

from dataclasses import replace

import numpy as np

from ..config import environment
from ..physics.brdf import BRDF, CompensatedBRDF, blend_lobes
from ..physics.diffuse.lambert import Lambert
from ..physics.g2 import lambda_phi_entry
from ..physics import smith_table
from ..physics.ndf import SlopeSpaceNDF
from . import compose
from .compiler import CLIENT
from .compose import Components
from .kernel import PARTS, Kernel, loops_of

#: numba installed (a regular dependency; without it everything runs on numpy) and not
#: switched off with BRDF_FAST=0. Read once; numba itself is imported only by the
#: background thread, with the first generated module (~0.5 s off the server's start).
ENABLED = (importlib.util.find_spec("numba") is not None
           and environment().fast)

log = logging.getLogger("uvicorn.error")   # uvicorn shows its own loggers' lines

#: CPU seconds of numpy work on one model part after which its loops are compiled (rent or
#: buy). A loop compiles in ~1.4-1.5 CPU-s (means over the 391 compiles of one full test run:
#: f_loop 1.36, f_deg_loop 1.45, albedo_rows 1.47), so f costs ~2.8 s, albedo ~1.5 s: the rent
#: is a third of the cheaper part, and a model in use spends at most RENT_SECONDS more than
#: its compile before it runs compiled; one used in passing spends no compile. Measured on a
#: live server: a Beckmann + conductor + Burley model dragged (five figures a round, ~20
#: rounds/s, a few ms of numpy work each) had its f loops ready after 12 s.
RENT_SECONDS = 0.5

#: keyed by (components, part): a part is ready, failed or queued on its own
_ready: dict[tuple[Components, str], Kernel] = {}
_failed: dict[tuple[Components, str], str] = {}
_queue: list[tuple[Components, str]] = []
_cv = threading.Condition()
_worker: threading.Thread | None = None
_told_numpy: set[tuple[Components, str]] = set()
#: CPU seconds of numpy work done so far on each model part that is not compiled
_rent: dict[tuple[Components, str], float] = {}
_compile_locks: dict[tuple[Components, str], threading.Lock] = {}
_compiler = CLIENT


def components(brdf: BRDF) -> Components | None:
    """The components that fix a model's loops, or None if they cannot be compiled."""
    if getattr(brdf, "numpy_only", False):
        return None          # the principled BRDF: numpy
    ndf = brdf.ndf
    if not isinstance(ndf, SlopeSpaceNDF):
        return None
    if brdf.g2.isotropic_only and not ndf.isotropic:
        return None          # numpy refuses it with its own message
    lp = lambda_phi_entry(brdf.lambda_phi) if brdf.g2.needs_phi else None
    if brdf.g2.needs_phi and lp is None:
        return None          # a λ(φ) that is not registered (no scalar formula)
    diffuse = Lambert if brdf.diffuse is None else type(brdf.diffuse)
    c = Components(type(ndf), brdf.masking, brdf.g2, type(brdf.fresnel), lp, diffuse)
    return c if c.complete() else None


def lookup(brdf: BRDF, part: str) -> Kernel | None:
    """The kernel of ``brdf``'s model if its loops for ``part`` are ready, else None: the
    caller then does the work on numpy inside :func:`numpy_path`."""
    if not ENABLED:
        return None
    c = components(brdf)
    if c is None:
        return None
    key = (c, part)
    kernel = _ready.get(key)
    if kernel is None and key not in _failed and key not in _told_numpy:
        _told_numpy.add(key)
        log.info("numpy path for %s (%s): its compiled loops are not ready yet (compiled "
                 "after %.1f s of numpy work on it)", c.label, part, RENT_SECONDS)
    return kernel


@contextlib.contextmanager
def numpy_path(brdf: BRDF, part: str):
    """Around the numpy work done for ``brdf``'s ``part`` because :func:`lookup` gave None:
    its CPU seconds (this thread's) are added to the model part's rent, and the part is
    queued for compiling, at the front, once the rent reaches RENT_SECONDS."""
    start = time.thread_time()
    try:
        yield
    finally:
        if ENABLED and (c := components(brdf)) is not None:
            key = (c, part)
            with _cv:
                rent = _rent[key] = _rent.get(key, 0.0) + time.thread_time() - start
            if rent >= RENT_SECONDS:
                _enqueue([key], front=True)


def compile_now(brdf: BRDF, part: str | None = None) -> Kernel | None:
    """The kernel of ``brdf``'s model with the loops of ``part`` (every part: None)
    compiled (or loaded) in this thread if needed. From a thread other than the main one
    (the server's background table builder) loops not in numba's cache are compiled by the
    compiler process first, then loaded here: numba compiling in that thread held the
    server's GIL for seconds against its first requests."""
    if not ENABLED:
        return None
    c = components(brdf)
    if c is None:
        return None
    kernel = None
    for key in ((c, p) for p in ((part,) if part is not None else PARTS)):
        if threading.current_thread() is not threading.main_thread() and key not in _ready:
            _compile_elsewhere(key)
        if (kernel := _build(key)) is None:
            return None
    if part is None:
        kernel.warm()   # the kernel handed back runs every loop compiled (each part's own
    return kernel       # kernel warmed only its part; a no-op where they share the loops)


def wait(brdf: BRDF, timeout: float, part: str) -> Kernel | None:
    """The kernel of ``brdf``'s model with its loops for ``part``, waiting at most
    ``timeout`` seconds for the background thread (they go to the front of its queue);
    None if not ready by then. For work that is much cheaper compiled, such as a table
    build."""
    if not ENABLED or (c := components(brdf)) is None or (key := (c, part)) in _failed:
        return None
    if key not in _ready:
        _enqueue([key], front=True)
        deadline = time.monotonic() + timeout
        with _cv:
            while key not in _ready and key not in _failed and time.monotonic() < deadline:
                _cv.wait(max(deadline - time.monotonic(), 0.0))
    return _ready.get(key)


def start(loops) -> None:
    """Queue these (model, part) loops, in order, for the background thread."""
    if ENABLED:
        _enqueue([(c, part) for brdf, part in loops if (c := components(brdf)) is not None])


def ready() -> list[str]:
    return [f"{c.label} ({part})" for c, part in _ready]


@contextlib.contextmanager
def disabled():
    """Within the block :func:`lookup` gives None: every caller takes the numpy path
    (benchmarks compare the two side by side; tests take the reference from it)."""
    global ENABLED
    before, ENABLED = ENABLED, False
    try:
        yield
    finally:
        ENABLED = before


def f(brdf: BRDF, l, v) -> np.ndarray:
    """f(l, v): the compiled loop when the model's is ready, else BRDF.evaluate; the
    second lobe and the Kulla-Conty term as BRDF.evaluate adds them."""
    kernel = lookup(brdf, "f")
    if kernel is None:
        with numpy_path(brdf, "f"):
            return brdf.evaluate(l, v, ("f",))["f"]
    single = brdf.single() if isinstance(brdf, CompensatedBRDF) else brdf
    first = replace(single, lobe2=None, lobe_mix=0.0)
    out = kernel.f(first, l, v)
    if single.lobe2 is not None and single.lobe_mix > 0:
        out = blend_lobes(single.lobe_mix, out, kernel.f(replace(first, ndf=single.lobe2), l, v))
    if isinstance(brdf, CompensatedBRDF):
        out = out + brdf.multiscatter_f(l, v)
    return out


def f_deg(brdf: BRDF, theta_l, phi_l, theta_v, phi_v, out=None) -> np.ndarray | None:
    """f at angles in degrees (l at θ_l, φ_l; v at θ_v, φ_v; broadcast together) by the
    model's compiled loop, the directions built inside it, into ``out`` if given (a
    contiguous float64 array of the broadcast size); None when the model has no ready
    loops or is compensated (the caller builds directions and calls :func:`f`)."""
    if isinstance(brdf, CompensatedBRDF):
        return None           # its multiple-scattering term takes directions
    kernel = lookup(brdf, "f")
    if kernel is None:
        return None
    first = replace(brdf, lobe2=None, lobe_mix=0.0)
    f = kernel.f_deg(first, theta_l, phi_l, theta_v, phi_v, out)
    if brdf.lobe2 is not None and brdf.lobe_mix > 0:
        second = kernel.f_deg(replace(first, ndf=brdf.lobe2), theta_l, phi_l, theta_v, phi_v)
        f[...] = blend_lobes(brdf.lobe_mix, f, second)
    return f


def _enqueue(keys: list[tuple[Components, str]], front: bool = False) -> None:
    global _worker
    with _cv:
        for key in keys:
            if key in _ready or key in _failed:
                continue
            if front and key in _queue[1:]:
                _queue.remove(key)         # the head may be compiling: leave it there
            if key not in _queue and front:
                _queue.insert(1 if _queue else 0, key)   # behind the one being compiled
            elif key not in _queue:
                _queue.append(key)
        if _worker is None or not _worker.is_alive():
            _worker = threading.Thread(target=_work, name="kernel-compiler", daemon=True)
            _worker.start()
        _cv.notify_all()


def _work() -> None:
    """Make queued model parts ready one by one: loops not in numba's disk cache are
    compiled by the compiler process first (compiler.py: not under this process's GIL,
    at a lower priority), then loaded from the cache here."""
    while True:
        with _cv:
            while not _queue:
                _cv.wait()
            key = _queue[0]
        _build(key, _compile_elsewhere(key))
        with _cv:
            if key in _queue:
                _queue.remove(key)
            _cv.notify_all()


def _compile_elsewhere(key: tuple[Components, str]) -> str:
    """Have the compiler process put the loops of ``key`` (components, part) into numba's
    disk cache unless they are there already; the note for the log line that says they
    are ready."""
    if key in _failed:
        return ""
    c, part = key
    t0 = time.perf_counter()
    try:
        module = compose.load(c)
        if compose.cached(module, loops_of(part)):
            return ""
        reason = _compiler.compile(module.__file__, part)
    except OSError as exc:
        reason = f"{type(exc).__name__}: {exc}"
    if reason is not None:
        log.warning("compiler process: %s (compiling in the server instead)", reason)
        return ""
    return f"compiled by the compiler process in {time.perf_counter() - t0:.1f} s, then "


def _build(key: tuple[Components, str], note: str = "") -> Kernel | None:
    if key in _ready:
        return _ready[key]
    with _cv:
        lock = _compile_locks.setdefault(key, threading.Lock())
    with lock:
        if key in _ready or key in _failed:
            return _ready.get(key)
        c, part = key
        t0 = time.perf_counter()
        try:
            module = compose.load(c)
            kernel = Kernel(c, module)
            # a loop two parts share (smith_h) may be compiled in this process already
            had = {name for name in loops_of(part) if getattr(module, name).signatures}
            with compose.compiling(module):
                kernel.warm(part)
        except Exception as exc:   # a formula numba cannot compile: numpy serves it
            with _cv:
                _failed[key] = f"{type(exc).__name__}: {exc}"
                _cv.notify_all()
            log.warning("no compiled loops for %s (%s; numpy serves it): %s", c.label, part,
                        _failed[key])
            return None
        new = [getattr(module, name) for name in loops_of(part) if name not in had]
        hits = sum(sum(k.stats.cache_hits.values()) for k in new)
        how = ("compiled already with another part" if not new else
               "loaded from numba's cache" if hits == len(new) else "compiled")
        log.info("compiled loops ready for %s (%s): %s%s in %.1f s", c.label, part, note, how,
                 time.perf_counter() - t0)
        with _cv:
            _ready[key] = kernel
            _cv.notify_all()
        smith_table.COMPILED_H.setdefault(c.ndf, _smith_h(kernel))
        return kernel


def _smith_h(kernel: Kernel):
    """The Smith-table integrals of ``kernel``'s NDF compiled (None while switched off)."""
    return lambda ndf, a: kernel.smith_h(ndf, a) if ENABLED else None
