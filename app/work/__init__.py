"""Work that runs apart from the server's event loop and threads (pool.py).

``await run_heavy(fn, *args, cost=seconds)`` from a route: ``fn(*args)`` in a worker
process of the server's one pool, admitted at once (413 never fits, 503 + Retry-After not
now) and cut at the request's budget. ``close()`` from the application's lifespan, after
its ``yield``: every worker killed, so shutdown never waits for a running job.
What each route's work costs is in costs.py, the work itself in jobs.py.
"""
from __future__ import annotations

from ..config import environment
from ..integrate import budget
from .pool import HeavyPool

# costs and jobs (the models, the views, the data readers) are imported where used: a
# worker process unpickling pool._call imports this package first, and a pool of plain
# jobs (the tests') should not pay the whole application's import to start

_POOL: HeavyPool | None = None


def pool() -> HeavyPool:
    """The server's pool, made on first use (BRDF_HEAVY_WORKERS, BRDF_HEAVY_QUEUE,
    BRDF_MAX_SECONDS)."""
    global _POOL
    if _POOL is None:
        s = environment()
        _POOL = HeavyPool(s.heavy_workers, s.heavy_queue, s.max_seconds)
    return _POOL


async def run_heavy(fn, *args, cost: float = 0.0, fits: str = ""):
    """``fn(*args)`` in the pool; ``cost`` its predicted seconds on one worker, ``fits``
    what would fit when it cannot (said in the 413).

    Outside a request (no budget open: a command line, a script calling a route's
    function) there is no server to protect and no budget to keep: ``fn`` runs here, as
    integrate.cost.require admits all work there. (The CLI's export-model-csv once
    spawned a pool whose worker, importing the application under load, spent the whole
    BRDF_MAX_SECONDS before an 18-row table began: "busy" from a command line.)"""
    if budget.current() is None:
        return fn(*args)
    return await pool().run(fn, *args, cost=cost, fits=fits)


def is_heavy(view_name: str) -> bool:
    """Whether a view's work runs in the pool (it has an entry in costs.VIEW_COSTS)."""
    from . import costs
    return view_name in costs.VIEW_COSTS


async def view_answer(view_name: str, fmt: str, q, settings):
    """A heavy view's answer to the validated query ``q`` from the pool: (body, media
    type) for fmt json, csv or data; the figure (a dict) to render for svg or png."""
    from . import jobs
    jobs.judge(view_name, q, settings)
    return await run_heavy(jobs.view, view_name, fmt, jobs.query_state(q), settings)


def close() -> None:
    """Kill the pool's workers (at shutdown); a later run_heavy makes a new pool."""
    global _POOL
    if _POOL is not None:
        _POOL.close()
        _POOL = None
