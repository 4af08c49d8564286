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

After each collection (the browser at rest: the page reloaded, its garbage collected) the
browser's whole process tree is read, and a tree that has grown GROWTH_BOUND_MB past its
first such reading is due for a new browser (image.py swaps one in without stopping any
render): whatever the browser keeps that a collection does not return, the tree stays
within that bound by construction, instead of by a soak's luck. What is read is the
tree's *anonymous* proportional set size (Pss_Anon + Pss_Shmem of /proc/<pid>/
smaps_rollup): the browser's own heap, which a leak would grow. Its file-backed pages
(chromium's ~250 MB binary and libraries, clean, shared with every other Chromium on the
machine) are left out: their PSS is divided among whatever other Chromium processes run,
so it moved by ~110 MB between two readings of an idle tree when another engineer's
browser test started (2026-12-08, 1 500 lobe PNGs in one process: total PSS 325 <-> 440 MB,
anonymous 199-210 MB throughout), and is bounded by the files' size anyway.
"""
from __future__ import annotations

import asyncio
import logging
import os
import threading
from concurrent.futures import Future
from pathlib import Path

#: images between two collections: ~100 MB of garbage at most between them, and one
#: collection's ~0.1-0.2 s of the renderer spread over 20 exports of 0.5-2 s each
COLLECT_EVERY = 20
#: the DevTools command: a full (major) collection of the page's JavaScript heap
COMMAND = "HeapProfiler.collectGarbage"
#: seconds a collection may take before its future is left (the renderer is stuck, or
#: the browser gone: the next render finds out and restarts it)
COLLECT_TIMEOUT_S = 10.0

#: MB of anonymous memory the browser's tree may gain, at rest, over its first reading
#: (after COLLECT_EVERY images: its working set built) before it is replaced. Measured
#: (2026-12-08, bench/renderer_growth.py: 840 lobe PNGs, read after each collection):
#: 200 → 210 MB, ~1 MB a hundred images (the browser process with its launcher 48 → 53,
#: the renderer 96 → 101, ±5 with the collections' timing), so 24 MB is growth, not
#: noise, and at that pace a browser serves ~2 000 images before it is replaced. A new
#: browser costs 1.9-2.0 s of CPU and 3.0-4.7 s of wall time to start at load 10-16 on
#: 2 cores, ~190 MB while both run (docs/robustness.md §3), paid off the request path
GROWTH_BOUND_MB = 24.0
#: past the bound by this much more, the browser is replaced even while exports are
#: queued (otherwise it waits for the export queue to empty: the start's CPU then slows
#: no render); without it, exports that never stop would never let it be replaced
OVERDUE_MB = 24.0

log = logging.getLogger(__name__)


def descendants(pid: int) -> set[int] | None:
    """``pid`` and every process below it now (/proc's parent links); None where /proc
    cannot tell (not Linux, or the process gone)."""
    parent: dict[int, int] = {}
    try:
        entries = [d for d in os.listdir("/proc") if d.isdigit()]
    except OSError:
        return None
    for d in entries:
        try:
            parent[int(d)] = int(Path(f"/proc/{d}/stat").read_text().rsplit(")", 1)[1].split()[1])
        except (OSError, ValueError, IndexError):
            continue
    if pid not in parent:
        return None
    children: dict[int, list[int]] = {}
    for p, pp in parent.items():
        children.setdefault(pp, []).append(p)
    out, todo = set(), [pid]
    while todo:
        p = todo.pop()
        out.add(p)
        todo.extend(children.get(p, ()))
    return out


def tree_anon_mb(pid: int) -> float | None:
    """MB of anonymous memory (Pss_Anon + Pss_Shmem) of process ``pid`` and all its
    descendants; None where /proc cannot tell (not Linux, or the process gone)."""
    tree = descendants(pid)
    if tree is None:
        return None
    total = 0
    for p in tree:
        try:
            for line in Path(f"/proc/{p}/smaps_rollup").read_text().splitlines():
                if line.startswith(("Pss_Anon:", "Pss_Shmem:")):
                    total += int(line.split()[1])
        except (OSError, ValueError, IndexError):
            continue
    return total / 1024


def browser_pid(kaleido) -> int | None:
    """The pid of the process kaleido started (choreographer's launcher, the browser's
    tree below it), None if it has none."""
    return getattr(getattr(kaleido, "subprocess", None), "pid", None)


class Collector:
    """Counts a browser's images, asks its tabs for a collection every ``every``, then
    reads its tree (``read``: kaleido → MB or None) and says when it is ``due`` for
    replacement: ``bound_mb`` past the first reading, ``overdue`` ``overdue_mb`` further."""

    def __init__(self, every: int = COLLECT_EVERY, bound_mb: float = GROWTH_BOUND_MB,
                 overdue_mb: float = OVERDUE_MB, read=None):
        self.every = every
        self.bound_mb, self.overdue_mb = bound_mb, overdue_mb
        self.read = read if read is not None else (lambda k: _read_tree(k))
        self.images = 0
        #: the latest collection asked for (tests wait on it), None before the first
        self.last: Future | None = None
        #: the tree's first reading at rest (its working size), and the latest
        self.baseline_mb: float | None = None
        self.latest_mb: float | None = None
        self._browser = None          # the kaleido these counts are of
        #: called (no argument, on the browser's loop's executor) after each reading
        self.on_read = None
        self._lock = threading.Lock()

    def rendered(self, kaleido, loop: asyncio.AbstractEventLoop) -> None:
        """One more image drawn by ``kaleido`` (whose loop is ``loop``): every
        ``every``-th, a collection of each of its tabs and a reading of its tree, sent
        and not waited for. A new browser starts the counts afresh."""
        with self._lock:
            if kaleido is not self._browser:
                self._browser, self.images = kaleido, 0
                self.baseline_mb = self.latest_mb = None
            self.images += 1
            due = self.images % self.every == 0
        if due:
            self.last = asyncio.run_coroutine_threadsafe(self._collect_and_read(kaleido), loop)
            self.last.add_done_callback(_log_failure)

    async def _collect_and_read(self, kaleido) -> int:
        tabs = await _collect(kaleido)
        mb = await asyncio.get_running_loop().run_in_executor(None, self.read, kaleido)
        with self._lock:
            if mb is not None and kaleido is self._browser:
                self.latest_mb = mb
                if self.baseline_mb is None:
                    self.baseline_mb = mb
        if self.on_read is not None:
            self.on_read()
        return tabs

    def growth_mb(self) -> float:
        """MB the tree has grown at rest since its first reading (0 before two)."""
        with self._lock:
            if self.baseline_mb is None or self.latest_mb is None:
                return 0.0
            return self.latest_mb - self.baseline_mb

    @property
    def due(self) -> bool:
        """The browser has grown past ``bound_mb``: replace it when no export is queued."""
        return self.growth_mb() > self.bound_mb

    @property
    def overdue(self) -> bool:
        """Past ``bound_mb + overdue_mb``: replace it even with exports queued."""
        return self.growth_mb() > self.bound_mb + self.overdue_mb


def _read_tree(kaleido) -> float | None:
    pid = browser_pid(kaleido)
    return None if pid is None else tree_anon_mb(pid)


async def _collect(kaleido) -> int:
    """A full collection in each of ``kaleido``'s tabs; how many were asked."""
    tabs = list(kaleido.tabs.values())
    for tab in tabs:
        await asyncio.wait_for(tab.send_command(COMMAND), COLLECT_TIMEOUT_S)
    return len(tabs)


def _log_failure(future: Future) -> None:
    if not future.cancelled() and future.exception() is not None:
        log.info("renderer garbage collection not done: %r", future.exception())
