"""Waiting, from a test, until this process's heavy-work pool (app/work) has started its
worker, as a server's has soon after it starts."""
from __future__ import annotations

import asyncio
from concurrent.futures import ThreadPoolExecutor

from app import work


def started(seconds: float = 120.0) -> None:
    """Block until the pool's idle workers have started (HeavyPool.started), waited for
    in a thread of its own: the test's thread may be running an event loop already
    (Playwright's sync API, in an xdist worker that ran browser tests first)."""
    with ThreadPoolExecutor(1) as thread:
        thread.submit(asyncio.run, work.pool().started(seconds)).result()
