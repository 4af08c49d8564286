"""E(μ, α) tables out of the request path: built in the background, persisted, reused.

A build (table.py) takes about 1 s for the compiled lobes and 10–30 s for the others: too
long inside a request on a loaded machine. Whole tables are kept in memory (least recently
used first out, MEMORY_BYTES) and, given a directory by :func:`start` (``BRDF_CACHE_DIR``;
unwritable: memory only, logged), on disk as ``.npz`` named by a digest of key, grid and
code (:func:`code_version`): a restart or another worker reads what one built, changed code
never reads a stale table; a lock file per table lets one worker build while others wait.

:func:`start` queues the start-up tables (defaults.py) for one background thread,
then any table a request needs, ahead of those still queued. A request builds a missing
table in place (waits for one queued or building) only if predicted to end within
IN_REQUEST_SHARE (WAIT_SHARE) of its time left; otherwise it is queued, a 503
(:class:`~app.errors.Busy`) names it and ``method=auto`` takes the quadrature. Outside
a request it is built in place. (derivation: docs/tables.md §4)"""
from __future__ import annotations

import fcntl
import hashlib
import json
import logging
import os
import itertools
import queue
import threading
import time
from collections import OrderedDict
from functools import _CacheInfo
from pathlib import Path

import numpy as np
from scipy.interpolate import RectBivariateSpline

from ... import npz
from ...errors import Busy
from .. import budget
from . import table as tables

log = logging.getLogger("app")

#: Bytes of whole tables kept in memory (a 56×56 table with its spline: ~60 kB).
MEMORY_BYTES = 16 * 1024 * 1024
#: Tables waiting for the background builder at most; beyond it a request is told to retry.
QUEUE_SIZE = 16
#: Share of the request's time left a table may be predicted to take and be built in it.
IN_REQUEST_SHARE = 0.25
#: ... and of it a request may wait for a background build (idle: no worker's CPU taken)
WAIT_SHARE = 0.5
#: Roughness of the row whose time predicts a build's (tables.predict_build_seconds).
PROBE_ALPHA = 0.25
#: Build time assumed for a queued table not probed (compiled 56²: GGX 0.6, Beckmann 1.3 CPU-s)
STARTUP_GUESS_SECONDS = 1.5
#: How often a request waiting for a background build looks for its table.
WAIT_POLL_SECONDS = 0.02
#: Retry-After when a build's remaining time is unknown (another worker holds its lock).
RETRY_UNKNOWN = 5
#: Largest Retry-After (a prediction probed on numpy was once 20× the compiled build's time)
RETRY_MAX = 10

_lock = threading.RLock()
_memory: "OrderedDict[tuple, tables.ETable]" = OrderedDict()
_stats = {"hits": 0, "misses": 0}
_pending: dict[tuple, dict] = {}   # key -> {"predicted": s, "queued": (priority, t), "started": t|None}
#: (priority, order, key): a request's table (0) before the start-up ones (1) still queued
_queue: "queue.PriorityQueue[tuple]" = queue.PriorityQueue(QUEUE_SIZE)
_order = itertools.count()
#: accepting: queue tables for the background builder (from :func:`start` to :func:`stop`)
_state = {"directory": None, "thread": None, "accepting": False}


def _describe(key: tuple) -> str | None:
    """The key as text (None when a part has no stable name: not persisted)."""
    ndf_class, shape, masking, g2, lambda_phi, basis_p = key
    if lambda_phi is not None and not hasattr(lambda_phi, "name"):
        return None
    return json.dumps([ndf_class.name, [[n, float(v).hex()] for n, v in shape], masking.name,
                       g2.name, getattr(lambda_phi, "name", None),
                       None if basis_p is None else float(basis_p).hex(),
                       [tables.TABLE_N_Y, tables.TABLE_N_R, tables.SLOW_TABLE_N,
                        tables.COARSE_TABLE_N, tables.BUILD_TOL]])


_version: list[str] = []


def code_version() -> str:
    """A digest of the code a table's values depend on: the physics, the integration, the
    compiled kernels, and the numpy and scipy versions."""
    if not _version:
        import scipy
        root = Path(__file__).resolve().parent.parent
        h = hashlib.sha256(f"numpy {np.__version__} scipy {scipy.__version__}".encode())
        for sub in ("physics", "integrate", "kernels"):
            for path in sorted((root / sub).rglob("*.py")):
                h.update(path.relative_to(root).as_posix().encode())
                h.update(path.read_bytes())
        _version.append(h.hexdigest()[:16])
    return _version[0]


def _path(key: tuple) -> Path | None:
    directory, text = _state["directory"], _describe(key)
    if directory is None or text is None:
        return None
    digest = hashlib.sha256((code_version() + text).encode()).hexdigest()[:24]
    return directory / f"table-{digest}.npz"


def _save(path: Path, key: tuple, t: tables.ETable) -> None:
    tmp = path.with_suffix(f".{os.getpid()}.tmp")
    with open(tmp, "wb") as f:
        np.savez(f, key=np.array(_describe(key)), r=t.r, y=t.y, values=t.values,
                 numbers=np.array([t.error, t.measured, t.node_error, t.build_seconds,
                                   t.build_evaluations], dtype=float))
    os.replace(tmp, path)      # readers see the whole file or none


def _load(path: Path, key: tuple) -> tables.ETable | None:
    try:
        z = npz.read(path)
        if str(z["key"]) != _describe(key):
            return None
        r, y, values, numbers = z["r"], z["y"], z["values"], z["numbers"]
    except (OSError, ValueError, KeyError) as exc:
        log.warning("table cache: %s unreadable (%s); building it again", path.name, exc)
        return None
    base = None if key[-1] is None else table(key[:-1] + (None,))
    spline = RectBivariateSpline(r, y, values, kx=3, ky=3, s=0)   # as built: same inputs
    error, measured, node_error, seconds, evaluations = numbers.tolist()
    return tables.ETable(key, r, y, values, spline, error, measured, node_error, seconds,
                         int(evaluations), base)


class _FileLock:
    """An exclusive lock on ``<table>.lock`` (fcntl.flock: released if the process dies)."""

    def __init__(self, path: Path):
        self.path = path.with_suffix(".lock")

    def acquire(self, blocking: bool) -> bool:
        self.f = open(self.path, "a")
        try:
            fcntl.flock(self.f, fcntl.LOCK_EX | (0 if blocking else fcntl.LOCK_NB))
            return True
        except BlockingIOError:
            self.f.close()
            return False

    def release(self) -> None:
        fcntl.flock(self.f, fcntl.LOCK_UN)
        self.f.close()


def _nbytes(t: tables.ETable) -> int:
    return t.values.nbytes + t.spline.get_coeffs().nbytes + t.r.nbytes + t.y.nbytes + 2048


def _remember(key: tuple, t: tables.ETable) -> tables.ETable:
    with _lock:
        _memory[key] = t
        _memory.move_to_end(key)
        while len(_memory) > 1 and sum(_nbytes(x) for x in _memory.values()) > MEMORY_BYTES:
            _memory.popitem(last=False)
    return t


def _ready(key: tuple) -> tables.ETable | None:
    with _lock:
        t = _memory.get(key)
        if t is not None:
            _memory.move_to_end(key)
            return t
    path = _path(key)
    if path is not None and path.exists():
        t = _load(path, key)
        if t is not None:
            return _remember(key, t)
    return None


def _build(key: tuple) -> tables.ETable:
    """Build (or, under the lock, find another worker's file), persist and remember."""
    base = None if key[-1] is None else table(key[:-1] + (None,))
    path = _path(key)
    lock = None
    if path is not None:
        lock = _FileLock(path)
        if not lock.acquire(blocking=budget.current() is None):
            raise Busy(f"the {table_name(key)} is being built by another worker", RETRY_UNKNOWN,
                       what=table_name(key))
    try:
        found = _ready(key) if path is not None else None
        if found is not None:
            return found
        b = budget.current()
        notes = len(b.notes) if b else 0
        with _lock:
            _stats["misses"] += 1
        t = tables.build_for_key(key, base)
        if b is not None and len(b.notes) > notes:
            return t            # cut short by the request's budget: answered, not kept
        if path is not None:
            try:
                _save(path, key, t)
            except OSError as exc:
                log.warning("table cache: cannot write %s (%s); kept in memory", path, exc)
        return _remember(key, t)
    finally:
        if lock is not None:
            lock.release()


def table_name(key: tuple) -> str:
    ndf_class, shape, masking, g2, _, basis_p = key
    shape_text = "".join(f", {n}={v:g}" for n, v in shape)
    basis = "F = 1" if basis_p is None else f"Schlick basis p={basis_p:g}"
    return (f"E(μ, α) table of ndf={ndf_class.name}{shape_text}, masking={masking.name}, "
            f"g2={g2.name} ({basis})")


def predict_seconds(key: tuple) -> float:
    """Seconds a build of ``key`` is predicted to take (tables.predict_build_seconds)."""
    return tables.predict_build_seconds(key, PROBE_ALPHA,
                                        key[-1] is None or _ready(key[:-1] + (None,)) is not None)


def _queue_build(key: tuple, predicted: float, priority: int = 0) -> dict:
    with _lock:
        entry = _pending.get(key)
        if entry is None and not _state["accepting"]:
            raise Busy(f"the {table_name(key)} would take ~{predicted:.0f} s to build, more than "
                       "this request has, and no background builder runs here (a server "
                       "started normally has one)", RETRY_UNKNOWN, what=table_name(key))
        if entry is None:
            try:
                _queue.put_nowait((priority, next(_order), key))
            except queue.Full:
                raise Busy(f"{QUEUE_SIZE} tables are waiting to be built; the {table_name(key)} "
                           "is not among them yet", RETRY_UNKNOWN, what=table_name(key)) from None
            entry = _pending[key] = {"predicted": predicted, "queued": (priority, time.time()),
                                     "started": None}
            _ensure_thread()
        return entry


def _seconds_left(key: tuple, entry: dict, floor: float = 0.0) -> float:
    """Seconds until the build should be done: its own prediction left, plus those ahead
    (a running one counted at least ``floor``)."""
    with _lock:
        now = time.time()
        ahead = sum(e["predicted"] for k, e in _pending.items()
                    if k != key and e["queued"] <= entry["queued"] and e["started"] is None)
        running = [e["predicted"] - (now - e["started"]) for e in _pending.values() if e["started"]]
    own = entry["predicted"] if entry["started"] is None else 0.0
    return own + ahead + sum(max(r, floor) for r in running)


def _wait_built(key: tuple, entry: dict, b) -> tables.ETable | None:
    """A background build's table, waited for if due within WAIT_SHARE of the time left
    (the start-up tables are queued before any request: a 503 for one due in 1 s)."""
    end = time.perf_counter() + WAIT_SHARE * (b.seconds - b.elapsed())
    if _seconds_left(key, entry) > end - time.perf_counter():
        return None
    while time.perf_counter() < end and key in _pending and key not in _memory:
        time.sleep(WAIT_POLL_SECONDS)
    return _ready(key)


def _worker() -> None:
    while True:
        key = _queue.get()[-1]
        with _lock:
            entry = _pending.get(key)
            if entry is None or entry["started"] is not None:
                _queue.task_done()       # promoted (see table), built or being built
                continue
            entry["started"] = time.time()
        try:
            t0 = time.perf_counter()
            _build(key)          # a new thread has no request budget: a whole build
            log.info("built the %s in %.1f s", table_name(key), time.perf_counter() - t0)
        except Exception:    # a build that fails must not stop the builder
            log.exception("building the %s failed", table_name(key))
        finally:
            with _lock:
                _pending.pop(key, None)
            _queue.task_done()


def _ensure_thread() -> None:
    with _lock:
        if _state["thread"] is None or not _state["thread"].is_alive():
            _state["thread"] = threading.Thread(target=_worker, name="table-builder", daemon=True)
            _state["thread"].start()


# ----------------------------------------------------------------------- API

def table(key: tuple) -> tables.ETable:
    """The whole table for ``key`` (module docstring); raises Busy in a request when it is
    being built, or would take too long to build here."""
    t = _ready(key)
    if t is not None:
        with _lock:
            _stats["hits"] += 1
        return t
    b = budget.current()
    if b is None:
        return _build(key)
    with _lock:
        entry = _pending.get(key)
        if entry is not None and entry["started"] is None and entry["queued"][0] > 0:
            try:     # a start-up table a request needs: built next (the worker skips the
                _queue.put_nowait((0, next(_order), key))   # copy left in the queue)
                entry["queued"] = (0, time.time())
            except queue.Full:
                pass
    if entry is not None and (t := _wait_built(key, entry, b)) is not None:
        return t
    if entry is None:
        predicted = predict_seconds(key)
        if predicted <= IN_REQUEST_SHARE * (b.seconds - b.elapsed()):
            try:
                return _build(key)
            except tables.TableTooSlow:     # slower than predicted (the machine is loaded)
                predicted = max(predicted, b.seconds)
        entry = _queue_build(key, predicted)
    retry = int(np.ceil(min(max(1.0, _seconds_left(key, entry, 1.0)), RETRY_MAX)))
    raise Busy(f"the {table_name(key)} is being built (~{entry['predicted']:.0f} s, outside this "
               "request); retry after the time given, or use method=quadrature", retry, what=table_name(key))


def table_if_ready(key: tuple) -> tables.ETable | None:
    """The table for ``key`` if in memory or on disk now, else None: ``method=auto`` then
    takes the quadrature, neither building nor queueing a table nobody asked for."""
    return _ready(key)


def building() -> list[str]:
    """The tables queued or being built, by name."""
    with _lock:
        return [table_name(k) for k in _pending]


def start(directory: str | os.PathLike | None, keys: list[tuple] | None = None) -> Path | None:
    """Use ``directory`` for persisted tables (created if missing; None: memory only) and
    queue ``keys`` (:func:`default_keys` of the default models) for the background builder.
    Returns the directory in use (None when it is not writable)."""
    _state["directory"], _state["accepting"] = None, True
    if directory is not None:
        path = Path(directory)
        try:
            path.mkdir(parents=True, exist_ok=True)
            (probe := path / f".write-test-{os.getpid()}").write_bytes(b"")
            probe.unlink()
            _state["directory"] = path
        except OSError as exc:
            log.warning("table cache: %s is not writable (%s); tables kept in memory only", path, exc)
    for key in (keys or []):
        if _ready(key) is None:
            try:    # not probed: start-up is not delayed; the builder takes its time
                _queue_build(key, STARTUP_GUESS_SECONDS, priority=1)
            except Busy:
                break
    return _state["directory"]


def stop() -> None:
    """Queue no more builds (those queued still finish) and forget the directory."""
    _state["directory"], _state["accepting"] = None, False


def wait(timeout: float | None = None) -> bool:
    """Block until the background builder has nothing left (tests, the CLI); False on timeout."""
    end = None if timeout is None else time.monotonic() + timeout
    while _pending:
        if end is not None and time.monotonic() > end:
            return False
        time.sleep(0.05)
    return True


def cache_info() -> _CacheInfo:
    with _lock:
        return _CacheInfo(_stats["hits"], _stats["misses"], None, len(_memory))


def cache_clear() -> None:
    """Forget the tables in memory (not on disk) and the counts."""
    with _lock:
        _memory.clear()
        _stats.update(hits=0, misses=0)
