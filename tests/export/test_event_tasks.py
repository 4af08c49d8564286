"""The browser's finished event tasks are not kept export after export (choreographer 1.4
keeps one per event kaleido subscribes to, and never drops it: the server's memory grew by
~8 kB an export in the soak's mix)."""
from __future__ import annotations

import asyncio
from concurrent.futures import ThreadPoolExecutor
from types import SimpleNamespace

import pytest

from app.export.image import forget_finished_event_tasks

#: the tasks one render may leave pending (still running when its image is back); a
#: render adds ~10 (Page.lifecycleEvent callbacks), so N renders kept would be ~10 N
PENDING_BOUND = 12
RENDERS = 12


def test_finished_tasks_are_dropped_and_running_ones_kept():
    async def scenario():
        release = asyncio.Event()

        async def quick():
            return None

        async def waiting():
            await release.wait()

        finished = [asyncio.create_task(quick()) for _ in range(5)]
        running = asyncio.create_task(waiting())
        await asyncio.sleep(0)                      # the quick ones finish
        broker = SimpleNamespace(_background_tasks_cancellable={*finished, running})
        dropped = forget_finished_event_tasks(SimpleNamespace(_broker=broker))
        left = set(broker._background_tasks_cancellable)
        release.set()
        await running
        return dropped, left, running

    # in a thread of its own: a session's Playwright (the browser tests, sync API) keeps an
    # event loop running in this one, where asyncio.run refuses to start
    with ThreadPoolExecutor(1) as pool:
        dropped, left, running = pool.submit(asyncio.run, scenario()).result()
    assert dropped == 5
    assert left == {running}


def test_a_choreographer_without_the_set_is_left_alone():
    assert forget_finished_event_tasks(SimpleNamespace()) == 0
    assert forget_finished_event_tasks(SimpleNamespace(_broker=SimpleNamespace())) == 0


@pytest.mark.e2e
def test_renders_do_not_accumulate_event_tasks(renderer):
    figure = {"data": [{"type": "scatter", "x": [0, 1, 2], "y": [1, 0, 1]}],
              "layout": {"title": {"text": "tasks"}}}
    kept = []
    for _ in range(RENDERS):
        png = renderer.render(figure, "png", 300, 200, 1.0)
        assert png[:8] == b"\x89PNG\r\n\x1a\n"
        broker = renderer._kaleido._broker
        kept.append(len(broker._background_tasks_cancellable))
    assert max(kept) <= PENDING_BOUND, kept
