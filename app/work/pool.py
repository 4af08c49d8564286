"""Heavy work apart from the cheap: a bounded pool of worker processes.

An upload's summary, an export, a batch, a fit or a large image ran in the server's own
threads, where the GIL let one of them starve every slider request of its worker
(issue 36: p99 70 ms → 13 s under one heavy mix). Here each runs in a worker *process*:

* ``workers`` processes (BRDF_HEAVY_WORKERS, default 1) run one job each; at most
  ``queue`` more (BRDF_HEAVY_QUEUE, default 4) wait. Admission is decided at once:
  - a job whose predicted cost (seconds on one worker) exceeds the time budget can never
    fit: :class:`~app.errors.TooLarge` (413) naming BRDF_MAX_SECONDS and what would fit;
  - a job that does not fit *now* (queue full, or the wait ahead plus its cost past the
    budget): :class:`~app.errors.Busy` (503 + Retry-After);
* an admitted job is cut at the request's budget (what is left of BRDF_MAX_SECONDS, or all
  of it outside a request): the caller gets Busy (503) saying it was stopped, and the job
  is left on its process to end by itself (it checks the same budget); the next job on
  that process waits for it, and one still running RUNAWAY_SECONDS later is killed and
  its process replaced, the others keep running;
* :meth:`HeavyPool.close` kills every worker at once, so a graceful shutdown ends within
  its timeout whatever runs (concurrent.futures' own exit hook joins running jobs: that
  was the SIGTERM that hung until SIGKILL).

Each worker is a one-process ``ProcessPoolExecutor`` (its process known, so one overrun
kills one job only), started with ``spawn``: the server's threads (uvicorn, numba, the
table builders) make ``fork`` unsafe. ``fn`` and its arguments must be picklable: a
module-level function and plain data.
"""
from __future__ import annotations

import asyncio
import importlib
import logging
import math
import multiprocessing
import os
import threading
import time
import traceback
from concurrent.futures import Future, ProcessPoolExecutor
from concurrent.futures.process import BrokenProcessPool

from pydantic import ValidationError

from .. import allocator
from ..errors import Busy, ParameterError, TooLarge
from ..integrate import budget
from ..integrate import cost as cost_model

#: worker processes and waiting places: settings BRDF_HEAVY_WORKERS, BRDF_HEAVY_QUEUE
WORKERS_ENV, QUEUE_ENV = "BRDF_HEAVY_WORKERS", "BRDF_HEAVY_QUEUE"
DEFAULT_WORKERS, DEFAULT_QUEUE = 1, 4
#: seconds a killed worker's end is waited for (SIGKILL ends it at once; the wait reaps it)
KILL_GRACE_SECONDS = 0.5
#: seconds past the request's budget (BRDF_MAX_SECONDS) a job's process is killed: the
#: job's own cost checks and cooperative cuts come first (a 413 from a worker's cost
#: probe needs ~0.1-0.3 s, which a kill at the budget itself took from a tiny budget);
#: the rest of cost.GRACE_SECONDS is for sending the answer
KILL_AFTER_SECONDS = 0.5
#: seconds a job whose caller stopped waiting for it (its budget ran out) is left to end
#: by itself before its process is killed. A job cuts itself at its budget (between
#: tiles, rows, orders: integrate/budget.py), so it usually ends a moment later; killing
#: it at once threw away a warmed process whose replacement costs ~3 s of CPU (an
#: interpreter importing the application, numba and the default loops: jobs.warm_up)
#: and left the pool without a worker meanwhile — on a loaded machine, where the niced
#: job is late, at nearly every request with a small budget. A job that never checks its
#: budget is still killed, this much later.
RUNAWAY_SECONDS = 2.0
#: scheduling niceness added to each worker (man 2 nice): on a machine with as many busy
#: processes as cores, the kernel gives the server's own process (cheap requests) the CPU
#: first; without it a heavy job took its core's share from the event loop (cheap p50
#: 2.9 → 19 ms at load 14 on 2 cores, tests/robustness/test_heavy_pool.py)
WORKER_NICENESS = 10
#: the module a new worker imports at once (the routes' jobs and what they use), calling
#: its ``warm_up()`` if it has one
WARM_MODULE = "app.work.jobs"
#: weight of the newest job in the running mean of job seconds (Retry-After's estimate)
MEAN_WEIGHT = 0.3
#: Retry-After of a job refused while its worker starts: a spawned worker's start took
#: 2-8 s here under load
START_RETRY_SECONDS = 3


class _Worker:
    """One process that runs one job at a time, and can be killed alone."""

    def __init__(self, context, warm: str | None):
        self.context, self.warm = context, warm
        self.executor = ProcessPoolExecutor(max_workers=1, mp_context=context,
                                            initializer=_start, initargs=(WORKER_NICENESS, warm))
        # start the process now, not at the first job: a spawned interpreter took > 1 s
        # to start under load, which the next job's budget would pay; done once started
        self.spawned = time.perf_counter()
        self.ready = self.executor.submit(int)
        self.start_seconds: float | None = None
        self.ready.add_done_callback(self._measure)
        #: the job a caller left running (its budget ran out), and when it counts as a
        #: runaway (perf_counter): the next job waits for it to end (HeavyPool._drained)
        self.leftover: Future | None = None
        self.runaway_at = math.inf

    def _measure(self, _future) -> None:
        self.start_seconds = time.perf_counter() - self.spawned

    def kill(self, wait: bool = False) -> None:
        """End the process now (SIGKILL: its work is pure computation, nothing to tidy),
        without joining its job. Reaped by a thread unless ``wait``: a killed process
        holding a large heap took ~0.3-0.5 s to go under load, which the event loop (and
        the answer of the request it ran for) waited in join()."""
        processes = list((self.executor._processes or {}).values())
        for p in processes:
            p.kill()
        if wait:
            for p in processes:
                p.join(KILL_GRACE_SECONDS)
        elif processes:
            threading.Thread(target=_reap, args=(processes,), daemon=True).start()
        self.executor.shutdown(wait=False, cancel_futures=True)


def _observed(job: Future) -> asyncio.Future:
    """``job`` as an awaitable of this loop whose end is always looked at: a job left
    running and then killed ends in BrokenProcessPool after its waiter has gone, which
    asyncio would log as an exception never retrieved."""
    waited = asyncio.wrap_future(job)
    waited.add_done_callback(lambda f: f.cancelled() or f.exception())
    return waited


def _reap(processes) -> None:
    for p in processes:
        p.join(KILL_GRACE_SECONDS)


class HeavyPool:
    """``workers`` processes, ``queue`` waiting places, jobs cut at ``max_seconds``;
    ``warm``: the module each worker imports as it starts."""

    def __init__(self, workers: int = DEFAULT_WORKERS, queue: int = DEFAULT_QUEUE,
                 max_seconds: float = 10.0, start_method: str = "spawn",
                 warm: str | None = WARM_MODULE):
        if workers < 1 or queue < 0:
            raise ValueError(f"{WORKERS_ENV} must be ≥ 1 and {QUEUE_ENV} ≥ 0")
        self.workers, self.queue, self.max_seconds = workers, queue, float(max_seconds)
        self._context, self._warm = multiprocessing.get_context(start_method), warm
        self._idle = [_Worker(self._context, warm) for _ in range(workers)]
        self._busy: set[_Worker] = set()
        self._running = 0
        self._waiters: list[asyncio.Future] = []
        self._mean_seconds = 1.0
        #: seconds the latest worker to finish its start took (None: none has yet)
        self._start_seconds: float | None = None
        self._closed = False

    # ------------------------------------------------------------------ admission
    def _budget(self) -> tuple[float, float]:
        """(the request's whole budget, what is left of it) in seconds: the request's own
        (its application's BRDF_MAX_SECONDS), or the pool's outside a request."""
        b = budget.current()
        return (self.max_seconds, self.max_seconds) if b is None else (b.seconds, b.seconds - b.elapsed())

    def _retry_after(self) -> int:
        ahead = self._running + len(self._waiters)
        return max(1, math.ceil(self._mean_seconds * (ahead / self.workers)))

    def admit(self, cost: float = 0.0, fits: str = "") -> None:
        """Refuse at once what can never fit (413) or does not fit now (503)."""
        if self._closed:
            raise Busy("the server is shutting down", retry_after=5, what="heavy work pool")
        whole, left = self._budget()
        if cost > whole:
            raise TooLarge("body", f"this work is predicted to take {cost:.1f} s; the limit is "
                           f"{whole:g} s (setting BRDF_MAX_SECONDS)"
                           + (f"; {fits}" if fits else ""), loc="body")
        if self._running + len(self._waiters) >= self.workers + self.queue:
            raise Busy(f"{self._running} heavy jobs run and {len(self._waiters)} wait (settings "
                       f"{WORKERS_ENV}={self.workers}, {QUEUE_ENV}={self.queue}); retry later",
                       retry_after=self._retry_after(), what="heavy work pool")
        wait = self._mean_seconds * (len(self._waiters) + max(0, self._running - self.workers + 1)) \
            if self._running >= self.workers else 0.0
        # work of unknown cost (0) that can start now is left to the worker's own checks
        if (wait or cost) and wait + cost > left:
            raise Busy(f"this work (~{cost:.1f} s) would start after ~{wait:.1f} s of queued "
                       f"work and end past the time budget (BRDF_MAX_SECONDS={whole:g})",
                       retry_after=self._retry_after(), what="heavy work pool")

    # ------------------------------------------------------------------ running
    async def run(self, fn, *args, cost: float = 0.0, fits: str = ""):
        """``fn(*args)`` in a worker process, admitted and cut as the module says. The
        worker runs it under the request's own budget (its clock: perf_counter is the
        system's monotonic clock, the same in every process), so its cooperative cuts
        and its cost checks see what the server's would; what it cut is added to the
        request's notes (the x-time-budget header)."""
        self.admit(cost, fits)
        request_budget = budget.current()
        start, seconds = ((request_budget.start, request_budget.seconds) if request_budget
                          else (time.perf_counter(), self.max_seconds))
        kill_at = start + seconds + KILL_AFTER_SECONDS
        worker = await self._take(kill_at)
        self._busy.add(worker)
        started, healthy, job = time.perf_counter(), False, None
        loop = asyncio.get_running_loop()
        try:
            if worker.leftover is not None:
                healthy = True    # kept while the job left on it ends by itself ...
                try:
                    await self._drained(worker, kill_at - KILL_AFTER_SECONDS - cost)
                except Busy:      # ... unless it died or ran past RUNAWAY_SECONDS
                    left = worker.leftover
                    healthy = not (left.done() and left.exception() is not None) \
                        and time.perf_counter() < worker.runaway_at
                    raise
                healthy = False
            if not worker.ready.done():
                healthy = True    # a starting worker left (refused, a client gone) is kept
                try:
                    await self._started(worker, kill_at - KILL_AFTER_SECONDS - cost)
                except Busy:      # ... unless it died as it started
                    healthy = not worker.ready.done() or worker.ready.exception() is None
                    raise
                healthy = False
            if worker.start_seconds is not None:
                self._start_seconds = worker.start_seconds
            try:      # a worker that died while idle refuses the job here, not in the await
                job = worker.executor.submit(_call, start, seconds, cost_model.memory_limit(), fn, args)
                # shielded: the wait ends at kill_at, the job may go on (left, below)
                outcome = await asyncio.wait_for(asyncio.shield(_observed(job)),
                                                 max(0.0, kill_at - time.perf_counter()))
            except TimeoutError:
                raise Busy(f"this work ran past the time budget (BRDF_MAX_SECONDS="
                           f"{seconds:g}) and was stopped; ask for less, or retry "
                           "when the server is less busy", retry_after=self._retry_after(),
                           what="heavy work pool") from None
            except BrokenProcessPool:
                raise Busy("the worker process running this work ended (out of memory?); "
                           "retry with less", retry_after=self._retry_after(),
                           what="heavy work pool") from None
            healthy = True
        finally:
            self._busy.discard(worker)
            if not healthy and job is not None and not job.done() and not self._closed:
                # its budget ran out (or its client went) while the job runs: it will
                # likely cut itself in a moment, so the process is kept, the job left on it
                worker.leftover, worker.runaway_at = job, kill_at + RUNAWAY_SECONDS
                loop.call_later(kill_at + RUNAWAY_SECONDS - time.perf_counter(), self._end_runaway, worker, job)
                self._give(worker)
            else:                 # a crash or a shutdown: a new worker
                self._give(worker) if healthy else self._renew(worker)
        self._mean_seconds += MEAN_WEIGHT * (time.perf_counter() - started - self._mean_seconds)
        return _unpack(outcome, request_budget)

    async def _drained(self, worker: _Worker, until: float) -> None:
        """Wait for the job left on ``worker`` to end, until ``until`` (the latest moment
        the new job could start and still end within its budget) or the left job's
        runaway time, whichever comes first; Busy after."""
        left = worker.leftover
        try:
            await asyncio.wait_for(asyncio.shield(_observed(left)),
                                   max(0.0, min(until, worker.runaway_at) - time.perf_counter()))
        except TimeoutError:
            raise Busy("the previous heavy job is still ending; retry in a moment",
                       retry_after=1, what="heavy work pool") from None
        except BrokenProcessPool:
            raise Busy("the heavy-work process ended; retry", retry_after=START_RETRY_SECONDS,
                       what="heavy work pool") from None
        worker.leftover, worker.runaway_at = None, math.inf

    def _end_runaway(self, worker: _Worker, job: Future) -> None:
        """RUNAWAY_SECONDS after its caller left: the job still running on an idle worker
        is killed, and the worker replaced (a worker taken meanwhile is the taker's)."""
        if worker.leftover is job and not job.done() and worker in self._idle:
            self._idle.remove(worker)
            self._running += 1
            self._renew(worker)

    async def _started(self, worker: _Worker, until: float) -> None:
        """Wait for ``worker``'s start (spawned at startup or after a cut: ~1-8 s, an
        interpreter importing the application) until ``until``, the latest moment the
        job could start and still end within its budget; Busy with the start's estimate
        after (a cold upload waited past its budget and was cut at 13.7 s)."""
        now = time.perf_counter()
        if self._start_seconds is not None and worker.spawned + self._start_seconds > until:
            # the last start took longer than this one has left: waiting would only spend
            # the request's budget on a 503 (each waited until its budget's end)
            raise Busy(f"the heavy-work process is still starting (the last start took "
                       f"{self._start_seconds:.1f} s); retry in a few seconds",
                       retry_after=max(1, math.ceil(worker.spawned + self._start_seconds - now)),
                       what="heavy work pool")
        try:
            await asyncio.wait_for(asyncio.shield(asyncio.wrap_future(worker.ready)),
                                   max(0.0, until - now))
        except BrokenProcessPool:
            raise Busy("the heavy-work process ended while it started; retry",
                       retry_after=START_RETRY_SECONDS, what="heavy work pool") from None
        except TimeoutError:
            raise Busy("the heavy-work process is still starting (a fresh interpreter "
                       "importing the application); retry in a few seconds",
                       retry_after=START_RETRY_SECONDS, what="heavy work pool") from None

    async def started(self, seconds: float = 120.0) -> None:
        """Wait until every idle worker has started (tests, warm-up)."""
        pending = [asyncio.wrap_future(w.ready) for w in self._idle if not w.ready.done()]
        if pending:
            await asyncio.wait_for(asyncio.gather(*pending), seconds)

    def _renew(self, worker: _Worker) -> None:
        """Kill ``worker`` (its job is abandoned) and, unless closing, put a new one in
        its place once the caller's answer is on its way (spawning takes the GIL for a
        moment, which a loaded server's loop would make the answer wait for)."""
        worker.kill()
        if self._closed:
            self._running -= 1
        else:
            asyncio.get_running_loop().call_soon(self._replace)

    def _replace(self) -> None:
        if self._closed:
            self._running -= 1
        else:
            self._give(_Worker(self._context, self._warm))

    async def _take(self, deadline: float) -> _Worker:
        """An idle worker, or the first one given back before ``deadline`` (Busy after)."""
        if self._idle:
            self._running += 1
            return self._idle.pop()
        waiter = asyncio.get_running_loop().create_future()
        self._waiters.append(waiter)
        try:
            worker = await asyncio.wait_for(waiter, max(0.0, deadline - time.perf_counter()))
        except TimeoutError:
            raise Busy("no worker became free within the time budget (BRDF_MAX_SECONDS="
                       f"{self.max_seconds:g})", retry_after=self._retry_after(),
                       what="heavy work pool") from None
        except asyncio.CancelledError:   # gone; a worker handed over meanwhile is passed on
            if waiter.done() and not waiter.cancelled() and waiter.exception() is None:
                self._running += 1
                self._give(waiter.result())
            raise
        finally:
            if waiter in self._waiters:
                self._waiters.remove(waiter)
        self._running += 1
        return worker

    def _give(self, worker: _Worker) -> None:
        self._running -= 1
        if self._closed:
            worker.kill()
            return
        while self._waiters:
            waiter = self._waiters.pop(0)
            if not waiter.done():
                waiter.set_result(worker)
                return
        self._idle.append(worker)

    def close(self) -> None:
        """Kill every worker now (a shutdown does not wait for running jobs)."""
        self._closed = True
        for worker in [*self._idle, *self._busy]:
            worker.kill(wait=True)
        self._idle.clear()
        for waiter in self._waiters:
            if not waiter.done():
                waiter.set_exception(Busy("the server is shutting down", retry_after=5,
                                          what="heavy work pool"))

    def stats(self) -> dict:
        return {"workers": self.workers, "queue": self.queue, "running": self._running,
                "waiting": len(self._waiters), "mean_seconds": round(self._mean_seconds, 3)}


def _start(niceness: int, warm: str | None) -> None:
    """A new worker: its niceness, the server's allocator setting (its large arrays go
    back to the system when freed: app/allocator.py), and the jobs' modules (``warm``)
    imported, and warmed up, before the first job (a cold import of the models and data
    readers took seconds of that job's budget; numba and LLVM, loaded by the first job
    running compiled loops, added ~150 MB inside it)."""
    os.nice(niceness)
    allocator.return_large_frees_to_the_system()
    if warm:
        module = importlib.import_module(warm)
        if hasattr(module, "warm_up"):
            module.warm_up()


def _call(start: float, seconds: float, memory_bytes: int, fn, args: tuple):
    """In the worker: ``fn(*args)`` under the request's budget (the same start and
    seconds) and memory limit. Every error comes back as a plain tuple: the application's
    own (their constructors take more than the message, which pickling cannot rebuild:
    the result thread failed to unpickle one and took the pool for broken), a validation
    error as the 422 naming its field, anything else as the internal error it is."""
    cost_model.set_memory_limit(memory_bytes)
    with budget.limit(seconds) as own:
        own.start = start
        try:
            return "ok", fn(*args), list(own.notes)
        except Busy as exc:
            return "busy", exc.message, exc.retry_after, exc.what
        except ParameterError as exc:
            return "parameter", exc.param, exc.message, exc.status, exc.loc
        except ValidationError as exc:        # a model built in the job (make_spec, vary)
            e = exc.errors(include_url=False)[0]
            name = ".".join(str(part) for part in e.get("loc", ())) or "body"
            return "parameter", name, f"{name}: {e.get('msg', '')}", 422, "query"
        except Exception as exc:  # noqa: BLE001 - a bug: the server answers 500 and logs it
            return "error", f"{type(exc).__name__}: {exc}", traceback.format_exc()


class WorkerError(RuntimeError):
    """An unexpected error in a heavy job (a bug): the server's 500, its traceback logged."""


def _unpack(outcome: tuple, request_budget):
    """The job's result (its cuts noted in the request's budget), or its error raised."""
    if outcome[0] == "busy":
        raise Busy(outcome[1], retry_after=outcome[2], what=outcome[3])
    if outcome[0] == "parameter":
        raise ParameterError(*outcome[1:])
    if outcome[0] == "error":
        logging.getLogger("uvicorn.error").error("heavy job failed:\n%s", outcome[2])
        raise WorkerError(outcome[1])
    if request_budget is not None:
        request_budget.notes.extend(outcome[2])
    return outcome[1]
