"""Chromium's renderer kept near its working size: a full JavaScript garbage collection
asked for every COLLECT_EVERY images.

kaleido reloads its tab after every image, and each reload leaves the page it drew
(plotly.js's heap, the figure) as garbage that V8 collects when its own heuristics say
so. Rendering the soak's lobe PNGs, one browser's renderer process grew by ~4-5 MB an
image, to 1.5 GB after 500 images, before a collection of its own took it to ~630 MB;
the soak read that climb as tens of MB/min of one server worker. A collection asked for
over DevTools (``HeapProfiler.collectGarbage``) took the renderer from 390-550 MB back to
180-210 MB, in 130-350 ms after 50 images. The memory is the browser's own garbage,
freed by the browser: no restart, no lost render.

The collection is sent on kaleido's loop once the image is answered (kaleido has
reloaded its tab by then), and not waited for: no request pays it.
"""
from __future__ import annotations

import asyncio
import logging
import threading
from concurrent.futures import Future

#: images between two collections: ~100 MB of garbage at most between them, and one
#: collection's ~0.1-0.2 s of the renderer spread over 20 exports of 0.5-2 s each
COLLECT_EVERY = 20
#: the DevTools command: a full (major) collection of the page's JavaScript heap
COMMAND = "HeapProfiler.collectGarbage"
#: seconds a collection may take before its future is left (the renderer is stuck, or
#: the browser gone: the next render finds out and restarts it)
COLLECT_TIMEOUT_S = 10.0

log = logging.getLogger(__name__)


class Collector:
    """Counts a browser's images and asks its tabs for a collection every ``every``."""

    def __init__(self, every: int = COLLECT_EVERY):
        self.every = every
        self.images = 0
        #: the latest collection asked for (tests wait on it), None before the first
        self.last: Future | None = None
        self._lock = threading.Lock()

    def rendered(self, kaleido, loop: asyncio.AbstractEventLoop) -> None:
        """One more image drawn by ``kaleido`` (whose loop is ``loop``): every
        ``every``-th, a collection of each of its tabs, sent and not waited for."""
        with self._lock:
            self.images += 1
            due = self.images % self.every == 0
        if due:
            self.last = asyncio.run_coroutine_threadsafe(_collect(kaleido), loop)
            self.last.add_done_callback(_log_failure)


async def _collect(kaleido) -> int:
    """A full collection in each of ``kaleido``'s tabs; how many were asked."""
    tabs = list(kaleido.tabs.values())
    for tab in tabs:
        await asyncio.wait_for(tab.send_command(COMMAND), COLLECT_TIMEOUT_S)
    return len(tabs)


def _log_failure(future: Future) -> None:
    if not future.cancelled() and future.exception() is not None:
        log.info("renderer garbage collection not done: %r", future.exception())
