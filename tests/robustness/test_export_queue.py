"""Image exports have their own bounded queue: TABS render, WAITING wait, the next is
refused at once with Busy (503 + Retry-After) instead of holding a server thread."""
from __future__ import annotations

import threading
import time

import pytest

from app.errors import Busy
from app.export import image


class SlowRenderer(image.ImageRenderer):
    """Renders nothing, slowly: the queue is what is tested, not Chromium."""

    def __init__(self, seconds: float):
        super().__init__()
        self.seconds = seconds

    def _render(self, figure, opts):
        time.sleep(self.seconds)
        return b"png"


def test_a_burst_beyond_the_queue_is_refused_at_once():
    renderer = SlowRenderer(1.0)
    results, lock = [], threading.Lock()

    def export():
        t0 = time.perf_counter()
        try:
            renderer.render({}, "png", 10, 10, 1)
            outcome = "ok"
        except Busy as exc:
            assert exc.retry_after >= 1 and "export" in exc.what
            outcome = "busy"
        with lock:
            results.append((outcome, time.perf_counter() - t0))

    threads = [threading.Thread(target=export) for _ in range(3 * renderer.places)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    ok = [s for o, s in results if o == "ok"]
    busy = [s for o, s in results if o == "busy"]
    assert len(ok) == renderer.places and len(busy) == 2 * renderer.places
    assert max(busy) < 0.5            # refused at once, not after waiting for a tab


def test_a_place_is_held_once_per_thread_and_given_back_on_error():
    renderer = SlowRenderer(0.0)
    with renderer.slot():
        assert renderer.render({}, "png", 10, 10, 1) == b"png"   # no second place taken
    for _ in range(renderer.places + 1):
        with pytest.raises(ZeroDivisionError), renderer.slot():
            1 / 0
    held = [renderer.slot() for _ in range(renderer.places)]
    # every place is free again: all can be taken at once from other threads
    taken = []

    def take(cm):
        cm.__enter__()
        taken.append(cm)

    threads = [threading.Thread(target=take, args=(cm,)) for cm in held]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    assert len(taken) == renderer.places
