"""What a computation will cost, known before it starts, against the request's limits.

A request's work is predicted from what it asks: BRDF (or integrand) evaluations × the
seconds one evaluation of the chosen model takes, measured once per model family by a probe
(:func:`seconds_per_evaluation`); its memory from the values it must hold at once (outputs,
one chunk of work). Then :func:`require` (outside a request there is no budget: no refusal):

* predicted beyond the whole time budget (BRDF_MAX_SECONDS + GRACE_SECONDS) or the memory
  budget (BRDF_MAX_REQUEST_BYTES): the input asks too much whatever the load — ``TooLarge``
  (413) naming the parameter and the setting, before any work;
* within the budget but beyond what is left of it before the request's first work (it
  waited for a worker thread): the machine is busy — ``Busy`` (503 + Retry-After), unless
  the work is negligible (NEGLIGIBLE_SECONDS). Later parts of a request are not refused
  (that would throw away what was computed): adaptive loops cut themselves short, fixed
  work in chunks stops at the deadline.
"""
from __future__ import annotations

import threading
import time
from functools import lru_cache

import numpy as np

from ..errors import Busy, TooLarge
from . import budget
from .cache import Keyed

#: Evaluations of the probe that measures a model's cost per evaluation (~1–10 ms).
PROBE_PAIRS = 4096
#: The prediction is multiplied by this before it is compared with the time left: a
#: probe on a warm cache underestimates a large request on a loaded machine.
SAFETY = 1.5
#: The memory budget of one request, set by the server at start-up (BRDF_MAX_REQUEST_BYTES).
_memory_limit = {"bytes": 1 << 30}
#: Seconds past BRDF_MAX_SECONDS a request may end: work that cannot be cut (a first
#: pass, one chunk) is started when predicted to end within it. Adaptive work stops
#: within BRDF_MAX_SECONDS itself (budget.py); this is the rest of the promise that no
#: request holds a worker longer than BRDF_MAX_SECONDS + 1 s.
GRACE_SECONDS = 1.0
#: Work predicted to take at most this long is never refused as busy: the refusal would
#: free the worker no sooner than the work itself, and cost the client a Retry-After of
#: at least 1 s. (On a loaded machine a request's one-time set-up — loading compiled code,
#: the cost probe — can spend its whole budget before this tiny work begins.)
NEGLIGIBLE_SECONDS = 0.05
_lock = threading.Lock()


def set_memory_limit(nbytes: int) -> None:
    _memory_limit["bytes"] = int(nbytes)


def memory_limit() -> int:
    return _memory_limit["bytes"]


def _family(brdf) -> tuple:
    """What the cost of one evaluation depends on (not α: the same code runs)."""
    ndf = brdf.ndf
    shape = tuple((p.name, getattr(ndf, p.name)) for p in ndf.shape_params)
    return (type(ndf), shape, brdf.masking.name, brdf.g2.name, brdf.fresnel.name,
            ndf.isotropic, brdf.lobe2 is not None and brdf.lobe_mix > 0,
            getattr(brdf, "multiscatter", None) is not None)


@lru_cache(maxsize=256)
def _probe(brdf_ref: Keyed) -> float:
    brdf = brdf_ref.value
    rng = np.random.default_rng(0)
    cos_t = rng.uniform(0.0, 1.0, (2, PROBE_PAIRS))
    phi = rng.uniform(0.0, 2 * np.pi, (2, PROBE_PAIRS))
    sin_t = np.sqrt(1.0 - cos_t ** 2)
    w = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), cos_t], axis=-1)
    brdf.evaluate(w[0, :8], w[1, :8], ("f",))          # imports, caches, Λ tables
    # CPU time of this thread, not wall time: the cost of the work whatever the load at
    # the moment of the probe (kept for the process); the time left is wall time.
    t0 = time.thread_time()
    brdf.evaluate(w[0], w[1], ("f", "D", "G2"))
    return (time.thread_time() - t0) / PROBE_PAIRS


def seconds_per_evaluation(brdf) -> float:
    """Seconds of one BRDF evaluation of this model family, measured once per process."""
    with _lock:
        return _probe(Keyed(brdf, _family(brdf)))


def require(seconds: float, nbytes: int, param: str, what: str) -> None:
    """Refuse work predicted to take ``seconds`` and hold ``nbytes`` when it cannot fit
    (module docstring). ``param`` is the request parameter that sets its size."""
    b = budget.current()
    if b is None:
        return
    if nbytes > memory_limit():
        raise TooLarge(param, f"{what} would hold ~{nbytes / 2**20:.0f} MiB at once, above "
                              f"BRDF_MAX_REQUEST_BYTES={memory_limit()}: ask for less")
    predicted = SAFETY * seconds
    if predicted > b.seconds + GRACE_SECONDS:
        raise TooLarge(param, f"{what} is predicted to take ~{predicted:.1f} s, beyond "
                              f"BRDF_MAX_SECONDS={b.seconds:g}: ask for less")
    left = b.seconds + GRACE_SECONDS - b.elapsed()
    worked = getattr(b, "worked", False)
    b.worked = True
    # Busy only before the request's first work: afterwards a refusal would throw away
    # what was computed, and the adaptive loops cut themselves short instead.
    if predicted > max(left, NEGLIGIBLE_SECONDS) and not worked:
        raise Busy(f"{what} needs ~{predicted:.1f} s and this request has {max(left, 0):.1f} s "
                   f"of BRDF_MAX_SECONDS={b.seconds:g} left (the server is busy): retry",
                   retry_after=int(np.ceil(predicted)), what="time budget")


def require_evaluations(brdf, evaluations: int, nbytes: int, param: str, what: str) -> None:
    """:func:`require` for ``evaluations`` BRDF evaluations of ``brdf``."""
    if budget.current() is None:
        return
    require(evaluations * seconds_per_evaluation(brdf), nbytes, param, what)


def check_deadline(what: str) -> None:
    """Between chunks of fixed work: once the request's budget is spent (the machine was
    slower than predicted, being busy), stop with Busy rather than hold the worker."""
    b = budget.current()
    if b is not None and b.elapsed() > b.seconds:
        raise Busy(f"{what} ran out of BRDF_MAX_SECONDS={b.seconds:g} (the server is busy): "
                   "retry", retry_after=int(np.ceil(b.seconds)), what="time budget")
