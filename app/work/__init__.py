"""Work that runs apart from the server's event loop and threads (pool.py).

``await run_heavy(fn, *args, cost=seconds)`` from a route: ``fn(*args)`` in a worker
process of the server's one pool, admitted at once (413 never fits, 503 + Retry-After not
now) and cut at the request's budget. ``close()`` from the application's lifespan, after
its ``yield``: every worker killed, so shutdown never waits for a running job.
"""
from __future__ import annotations

from ..config import environment
from .pool import HeavyPool

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
    what would fit when it cannot (said in the 413)."""
    return await pool().run(fn, *args, cost=cost, fits=fits)


def close() -> None:
    """Kill the pool's workers (at shutdown); a later run_heavy makes a new pool."""
    global _POOL
    if _POOL is not None:
        _POOL.close()
        _POOL = None
