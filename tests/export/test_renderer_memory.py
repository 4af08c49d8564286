"""Chromium's renderer does not keep the garbage of the images it drew (renderer_memory.py):
kaleido reloads its tab after each image, and V8 left each reload's heap for a collection
of its own, ~4-5 MB an image, up to 1.5 GB (the soak's +tens of MB/min of one worker)."""
from __future__ import annotations

import os
import time

from app.export import renderer_memory
from app.export.image import ImageRenderer

#: MB the renderer may grow over 2 × COLLECT_EVERY images after its first COLLECT_EVERY
#: (its working set is built by then); without collections it grew ~4-5 MB an image
GROWTH_BOUND_MB = 40


def _renderers(r: ImageRenderer) -> dict[int, int]:
    """pid → resident MB of the renderer processes of ``r``'s own browser (not those of
    another Chromium this test process drives: the session's Playwright browser keeps its
    pages, and their memory moved by 44 MB during one full run)."""
    out = {}
    for pid in renderer_memory.descendants(renderer_memory.browser_pid(r._kaleido)) or ():
        try:
            if b"--type=renderer" not in open(f"/proc/{pid}/cmdline", "rb").read():
                continue
            out[pid] = next(int(line.split()[1]) // 1024 for line in open(f"/proc/{pid}/status")
                            if line.startswith("VmRSS:"))
        except (OSError, ValueError, IndexError, StopIteration):
            continue
    return out


def _settled(r: ImageRenderer) -> int:
    """The renderers' MB once the last collection asked for (if any) is done."""
    last = getattr(getattr(r, "memory", None), "last", None)
    if last is not None:
        last.result(30)
    time.sleep(0.5)
    rss = _renderers(r)
    assert rss, "no renderer process found below the export browser"
    return sum(rss.values())


def test_the_renderer_does_not_keep_each_images_garbage(client):
    """The soak's images (lobe panels, each α its own figure): after its first
    COLLECT_EVERY images, 2 × COLLECT_EVERY more leave the renderer where it was."""
    every = renderer_memory.COLLECT_EVERY
    figures = [client.get(f"/api/v1/figures/lobe?alpha={0.05 + 0.01 * k:.2f}").json()
               for k in range(3 * every)]
    r = ImageRenderer(os.environ.get("BRDF_CHROMIUM") or None)
    try:
        # the README's test command installs Chromium: a render that fails is a failure,
        # not a skip (a skip here hid any error of the export itself)
        for k in range(every):
            r.render(figures[k], "png", 800, 500, 1)
        before = _settled(r)
        for k in range(every, 3 * every):
            r.render(figures[k], "png", 800, 500, 1)
        after = _settled(r)
    finally:
        r.close()
    assert after - before < GROWTH_BOUND_MB, (before, after)


def _tree(pid: int) -> set[int]:
    """``pid`` and its descendants now (none left: the empty set)."""
    return renderer_memory.descendants(pid) or set()


def _gone(pids: set[int], seconds: float) -> set[int]:
    """Those of ``pids`` still alive after up to ``seconds``."""
    t0 = time.monotonic()
    while True:
        alive = {p for p in pids if os.path.exists(f"/proc/{p}")}
        if not alive or time.monotonic() - t0 > seconds:
            return alive
        time.sleep(0.1)


def test_a_replaced_chromium_leaves_no_process_behind_and_the_next_image_is_drawn(client):
    """A real Chromium due for replacement (its bound set below any growth): a new one
    is swapped in, the old one's whole process tree exits, images go on being drawn."""
    figures = [client.get(f"/api/v1/figures/lobe?alpha={0.05 + 0.01 * k:.2f}").json()
               for k in range(4)]
    r = ImageRenderer(os.environ.get("BRDF_CHROMIUM") or None)
    r.memory.every = 2
    r.memory.bound_mb = -1e9          # due at its first reading
    try:
        for k in range(2):
            r.render(figures[k], "png", 400, 250, 1)
        first = renderer_memory.browser_pid(r._kaleido)
        old = _tree(first)
        assert len(old) >= 3, old     # the launcher, the browser, its renderer...
        r.memory.last.result(30)
        t0 = time.monotonic()
        while r.replaced < 1 and time.monotonic() - t0 < 60:
            time.sleep(0.1)
        assert r.replaced >= 1 and renderer_memory.browser_pid(r._kaleido) != first
        assert not _gone(old, 20)
        assert r.render(figures[2], "png", 400, 250, 1)[:8] == b"\x89PNG\r\n\x1a\n"
    finally:
        r.close()
