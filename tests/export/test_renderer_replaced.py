"""A browser whose memory at rest has grown past its bound is replaced (image.py,
renderer_memory.GROWTH_BOUND_MB): a new one is started beside it, later exports go to
it, the old one is closed only once the drawings it had in hand are done, and no export
is lost or waits for the start. Without the replacement, the export browser's tree grew
for as long as the server lived: the soak read its Chromium at +1.3 to +3.5 MB/min.

Browser stand-ins (they draw in DRAW_S and "grow" GROW_MB an image) replace Chromium: what
is tested is when the renderer swaps, and that the swap loses nothing; a real Chromium's
replacement is in test_renderer_memory.py."""
from __future__ import annotations

import asyncio
import threading
import time

from app.export import image

DRAW_S = 0.02
#: MB a stand-in browser's tree grows with each image it draws (a leak's pace, fast)
GROW_MB = 2.0
#: seconds the second and later browsers take to start
START_S = 0.3


class Browser:
    """kaleido's calls that the renderer makes, with a size that grows as it draws."""

    def __init__(self):
        self.mb = 200.0
        self.drawing = 0
        self.drawn = 0
        self.closed = False
        self.closed_while_drawing = False
        self.tabs: dict = {}          # renderer_memory's collection asks each tab: none here

    async def calc_fig(self, figure, opts):
        if self.closed:
            raise RuntimeError("browser closed")
        self.drawing += 1
        try:
            await asyncio.sleep(figure.get("draw_s", DRAW_S))
        finally:
            self.drawing -= 1
        if self.closed:
            raise RuntimeError("browser closed while drawing")
        self.drawn += 1
        self.mb += GROW_MB
        return b"png"

    async def close(self):
        self.closed_while_drawing |= self.drawing > 0
        self.closed = True


class Renderer(image.ImageRenderer):
    """Opens stand-in browsers, each on its own loop; every browser it opened is kept."""

    def __init__(self, every: int = 4):
        super().__init__()
        self.browsers: list[Browser] = []
        self.memory.every = every
        self.memory.read = lambda k: k.mb

    def _open(self):
        if self.browsers:
            time.sleep(START_S)
        loop = asyncio.new_event_loop()
        threading.Thread(target=loop.run_forever, daemon=True).start()
        self.browsers.append(Browser())
        return loop, self.browsers[-1]

    def _start(self) -> None:          # the first browser, as image.py's own _start does
        self._loop, self._kaleido = self._open()


def _burst(r: Renderer, n: int, figure=None) -> list:
    """n exports at once, each a client of its own; their answers (bytes or exception)."""
    out, lock = [], threading.Lock()

    def one():
        try:
            got = r.render(figure or {}, "png", 10, 10, 1)
        except Exception as exc:  # noqa: BLE001 - collected, asserted on below
            got = exc
        with lock:
            out.append(got)
    threads = [threading.Thread(target=one) for _ in range(n)]
    for t in threads:
        t.start()
    for t in threads:
        t.join(30)
    return out


def _wait(predicate, seconds: float = 5.0) -> bool:
    t0 = time.monotonic()
    while time.monotonic() - t0 < seconds:
        if predicate():
            return True
        time.sleep(0.01)
    return predicate()


def test_a_browser_past_its_bound_is_replaced_and_no_export_is_lost():
    r = Renderer()
    try:
        bound, every = r.memory.bound_mb, r.memory.every
        answers = []
        # bursts of the export queue's size, a pause between them longer than a start
        # (the soak's pattern: 20 exports a minute, idle between)
        for _ in range(10):
            answers += _burst(r, r.places)
            time.sleep(START_S + 0.1)
        _wait(lambda: not r._replacing)
        assert all(a == b"png" for a in answers), [a for a in answers if a != b"png"][:3]
        assert len(r.browsers) >= 2 and r.replaced == len(r.browsers) - 1, len(r.browsers)
        old = r.browsers[:-1]
        assert _wait(lambda: all(b.closed for b in old)), [b.closed for b in old]
        assert not any(b.closed_while_drawing for b in r.browsers)
        assert not r.browsers[-1].closed
        # none was let grow much past the bound: its first reading after `every` images,
        # then one every `every` images, a swap as soon as the queue empties after one
        for b in old:
            assert b.mb - 200.0 <= GROW_MB * every + bound + GROW_MB * (every + r.places), b.mb
    finally:
        r.close()


def test_a_drawing_in_hand_ends_on_the_old_browser_and_no_export_waits_for_the_start():
    r = Renderer(every=2)
    try:
        r.memory.bound_mb = 0.5       # due after the second reading
        for _ in range(4):
            assert r.render({}, "png", 10, 10, 1) == b"png"
        r.memory.last.result(5)
        first = r.browsers[0]
        # a long drawing taken before the swap; the swap starts while it draws
        slow = threading.Thread(target=lambda: r.render({"draw_s": 1.0}, "png", 10, 10, 1))
        slow.start()
        assert _wait(lambda: first.drawing == 1)
        r.memory.overdue_mb = 0.0     # replace even with this export queued
        r.memory.latest_mb = r.memory.baseline_mb + 10
        r._maybe_replace()
        assert _wait(lambda: len(r.browsers) == 2 and r._kaleido is r.browsers[1])
        # exports meanwhile go to the new browser, not after the old one's drawing
        t0 = time.perf_counter()
        assert r.render({}, "png", 10, 10, 1) == b"png"
        assert time.perf_counter() - t0 < 0.5
        assert not first.closed              # its drawing is not done yet
        slow.join(5)
        assert first.drawn >= 5 and not first.closed_while_drawing
        assert _wait(lambda: first.closed)   # closed once it was done
    finally:
        r.close()


def test_a_due_browser_waits_for_the_queue_to_empty():
    """Due but not overdue: no start while exports are queued (its CPU would slow them)."""
    r = Renderer(every=2)
    try:
        for _ in range(4):
            r.render({}, "png", 10, 10, 1)
        r.memory.last.result(5)
        r.memory.latest_mb = r.memory.baseline_mb + r.memory.bound_mb + 1   # due, not overdue
        with r.slot():                       # an export computing its figure
            r._maybe_replace()
            time.sleep(0.1)
            assert len(r.browsers) == 1
        assert _wait(lambda: len(r.browsers) == 2)   # the queue emptied: replaced
    finally:
        r.close()
