"""SVG and PNG of a Plotly figure, rendered by kaleido in ONE headless Chromium per
process, started on the first export and kept alive between requests.

The browser lives on an asyncio loop in one daemon thread; each export is a coroutine
submitted with ``run_coroutine_threadsafe``, whose own future carries its own result (or
exception), with a time limit; kaleido's tab queue serialises the rendering. (Not
``kaleido.start_sync_server()``: its thread dies silently when Chromium cannot start, and
its one queue for all callers can hand two threads each other's image.)

Exports have their own bounded queue: TABS render and WAITING wait for a tab; one more is
refused at once (:class:`ExportQueueFull`, 503 + Retry-After) rather than hold a server
thread that cheap requests need. A route takes its place with ``renderer.slot()`` before it
computes the figure. Without Chromium, :class:`ExportUnavailable` says what to install;
the API answers 503 and the page falls back to Plotly's in-browser export.
(derivation: docs/robustness.md §1, "Image exports")

The browser is replaced when its memory at rest has grown past a bound
(renderer_memory.GROWTH_BOUND_MB): a new one is started beside it off the request path,
later exports go to it, and the old one is closed once the drawings it had in hand are
done, so no export waits for a start or is lost (docs/robustness.md §3)."""
from __future__ import annotations

import asyncio
import atexit
import logging
import sys
import threading
import time
from concurrent.futures import Future
from contextlib import contextmanager

from ..config import environment
from ..errors import Busy
from ..integrate import budget
from .renderer_memory import Collector

log = logging.getLogger(__name__)

# Tabs rendering in parallel in the one browser. One: every tab is a renderer process,
# and the service runs on small machines; requests queue for the tab.
TABS = 1
# Exports that may wait for a tab while TABS render; beyond them 503 at once. Four
# places in all: a page exporting its panels together is served, 100 at once are not.
WAITING = 3
# Typical seconds of one export (compute and render a 1000×700 PNG, measured 0.5–2 s):
# the Retry-After of a full queue is this × the exports ahead.
EXPORT_SECONDS = 2
# Seconds one figure may take inside Chromium (kaleido's own limit), and the longest a
# request waits for its image, queueing behind others included.
RENDER_TIMEOUT_S = 30.0
WAIT_TIMEOUT_S = 60.0
# Seconds allowed for Chromium to start and load plotly.js.
START_TIMEOUT_S = 60.0
# Seconds a replaced browser is given to finish the drawings it had in hand before it is
# closed anyway: kaleido's own limit ends any drawing by then.
RETIRE_TIMEOUT_S = RENDER_TIMEOUT_S + 5.0

INSTALL_HINT = ("Server-side image export needs a Chromium browser: install it "
                "(Debian/Ubuntu: apt-get install chromium; elsewhere: kaleido_get_chrome) "
                "or point BRDF_CHROMIUM at one. The page's own export buttons work "
                "without it (they render in your browser).")

FORMATS = {"svg": "image/svg+xml", "png": "image/png"}


class ExportUnavailable(Busy):
    """No browser to render with (or it would not start, or it took too long): 503,
    the message says what to install."""

    def __init__(self, message: str):
        super().__init__(message, retry_after=int(START_TIMEOUT_S), what="image export")


class ExportQueueFull(Busy):
    """Every place of the export queue is taken: 503 + Retry-After, at once."""

    def __init__(self, places: int):
        super().__init__(f"{places} image exports are rendering or waiting for the renderer; "
                         "retry shortly (the page's own export buttons render in your browser)",
                         retry_after=EXPORT_SECONDS * places // TABS, what="image export queue")


class ImageRenderer:
    """One headless Chromium, started lazily, shared by every export of this process."""

    def __init__(self, browser_path: str | None = None):
        # None: kaleido's own search (BROWSER_PATH, then chromium/chrome on PATH).
        self.browser_path = browser_path
        self._lock = threading.Lock()
        self._loop: asyncio.AbstractEventLoop | None = None
        self._kaleido = None
        self._starting: Future | None = None      # the browser's start under way
        self.started_seconds: float | None = None   # how long the start took
        self.places = TABS + WAITING
        self._places = threading.BoundedSemaphore(self.places)
        self._held = threading.local()
        self._taken = 0                  # places taken now (the queue is empty at 0)
        #: a full JavaScript collection every few images, and the browser's size at rest
        #: after each (renderer_memory.py): past its bound, a new browser is swapped in
        self.memory = Collector()
        self.memory.on_read = self._maybe_replace
        self._inflight: dict[int, int] = {}     # id(kaleido) → drawings it has in hand
        self._drawn = threading.Condition(self._lock)
        self._replacing = False
        #: browsers replaced, and the last replacement's seconds to start the new one
        self.replaced = 0
        self.replace_seconds: float | None = None

    @contextmanager
    def slot(self):
        """A place in the export queue for the enclosed work (computing the figure and
        rendering it), or ExportQueueFull at once; a thread that holds one already
        (render() inside slot()) takes no second."""
        depth = getattr(self._held, "depth", 0)
        if depth == 0:
            if not self._places.acquire(blocking=False):
                raise ExportQueueFull(self.places)
            with self._lock:
                self._taken += 1
        self._held.depth = depth + 1
        try:
            yield
        finally:
            self._held.depth = depth
            if depth == 0:
                with self._lock:
                    self._taken -= 1
                self._places.release()
                self._maybe_replace()

    @property
    def running(self) -> bool:
        return self._kaleido is not None

    def _start(self) -> None:
        """Start the browser and make it the one exports use."""
        t0 = time.perf_counter()
        loop, k = self._open()
        self._loop, self._kaleido = loop, k
        self.started_seconds = time.perf_counter() - t0

    def _open(self):
        """A new browser: (its loop, running in a daemon thread, and its kaleido)."""
        # kaleido's logging library (logistro) parses sys.argv when imported and exits on
        # options it finds ambiguous ("--log" of our own CLI): hide our arguments from it.
        saved_argv, sys.argv = sys.argv, sys.argv[:1]
        try:
            import kaleido
            from choreographer.errors import ChromeNotFoundError
        except ImportError as e:          # kaleido is a dependency; be explicit anyway
            raise ExportUnavailable(f"kaleido is not installed ({e}). {INSTALL_HINT}") from None
        finally:
            sys.argv = saved_argv
        loop = asyncio.new_event_loop()
        thread = threading.Thread(target=loop.run_forever, name="kaleido", daemon=True)
        thread.start()

        async def open_browser():
            # mathjax=False: no LaTeX in our figures, and no CDN to fetch it from.
            opts = {"path": self.browser_path} if self.browser_path else {}
            k = kaleido.Kaleido(n=TABS, timeout=RENDER_TIMEOUT_S, mathjax=False, **opts)
            await k.open()
            return k

        try:
            k = asyncio.run_coroutine_threadsafe(open_browser(), loop).result(START_TIMEOUT_S)
        except ChromeNotFoundError:
            loop.call_soon_threadsafe(loop.stop)
            where = f" (looked for {self.browser_path})" if self.browser_path else ""
            raise ExportUnavailable(f"No Chromium found{where}. {INSTALL_HINT}") from None
        except Exception as e:  # noqa: BLE001 - any start failure means "unavailable"
            loop.call_soon_threadsafe(loop.stop)
            raise ExportUnavailable(f"Chromium did not start ({type(e).__name__}). "
                                    f"{INSTALL_HINT}") from None
        return loop, k

    def render(self, figure: dict, fmt: str, width: int, height: int, scale: float) -> bytes:
        """The figure as ``fmt`` ('svg' or 'png'), ``width``×``height`` CSS pixels, PNG
        pixels multiplied by ``scale``."""
        if fmt not in FORMATS:
            raise ValueError(f"format must be one of {', '.join(FORMATS)}")
        opts = {"format": fmt, "width": width, "height": height, "scale": scale}
        with self.slot():
            return self._render(figure, opts)

    def _browser(self):
        """(loop, kaleido) of the running browser: started by a thread of its own (once,
        whoever asks), waited for within what is left of the request's time budget (a
        first export under load waited the browser's start, 2-8 s, past it): Busy after,
        while the start goes on for the next request."""
        with self._lock:
            if self.running:
                return self._take()
            if self._starting is None:
                self._starting = Future()
                threading.Thread(target=self._start_into, args=(self._starting,),
                                 name="kaleido-start", daemon=True).start()
            starting = self._starting
        wait, cut = _wait_seconds()
        try:
            starting.result(min(wait, START_TIMEOUT_S))
        except TimeoutError:
            if cut:
                raise Busy("the image renderer (a headless Chromium) is starting; retry in a "
                           "few seconds", retry_after=EXPORT_SECONDS, what="image export") from None
            raise ExportUnavailable(f"Chromium did not start within {START_TIMEOUT_S:g} s. "
                                    f"{INSTALL_HINT}") from None
        with self._lock:
            if not self.running:      # closed meanwhile (a crash): the caller's retry starts it
                raise ExportUnavailable(f"Chromium stopped as it started. {INSTALL_HINT}")
            return self._take()

    def _take(self):
        """(loop, kaleido) of the current browser, counted as having one more drawing in
        hand until ``_done`` (under self._lock: a replacement cannot close it between)."""
        key = id(self._kaleido)
        self._inflight[key] = self._inflight.get(key, 0) + 1
        return self._loop, self._kaleido

    def _done(self, k) -> None:
        """A drawing taken with ``_take`` from ``k`` has ended (drawn, failed or cut)."""
        with self._lock:
            left = self._inflight.get(id(k), 1) - 1
            if left > 0:
                self._inflight[id(k)] = left
            else:
                self._inflight.pop(id(k), None)
            self._drawn.notify_all()

    def _start_into(self, started: Future) -> None:
        try:
            self._start()
            started.set_result(None)
        except BaseException as exc:  # noqa: BLE001 - handed to every request waiting for it
            started.set_exception(exc)
        finally:
            with self._lock:
                self._starting = None

    def _render(self, figure: dict, opts: dict) -> bytes:
        for attempt in (1, 2):
            loop, k = self._browser()
            wait, cut = _wait_seconds()
            if cut and wait <= 0:
                self._done(k)
                raise _past_budget()
            future = asyncio.run_coroutine_threadsafe(_calc_fig(k, figure, opts), loop)
            # counted until Chromium is done with it, not until the request stops waiting
            future.add_done_callback(lambda _f, k=k: self._done(k))
            try:
                image = future.result(wait)
            except TimeoutError:
                if cut:   # left to finish: a drawing cancelled mid-way can leave its tab
                    raise _past_budget() from None    # stuck for every later one
                future.cancel()
                raise ExportUnavailable(f"rendering took longer than {WAIT_TIMEOUT_S:g} s") from None
            except Exception:
                # A crashed or closed browser: start a fresh one, once.
                if attempt == 2:
                    raise
                self._close_if_current(k)
                continue
            if k is self._kaleido:     # not a browser being replaced: its counts are done
                self.memory.rendered(k, loop)
            return image
        raise AssertionError("unreachable")

    def _maybe_replace(self) -> None:
        """Start replacing the browser if its memory is past its bound (renderer_memory:
        ``due``) and no export is queued, or far past it (``overdue``) whatever the queue;
        once at a time, in a thread of its own."""
        if not (self.memory.due and self._taken == 0 or self.memory.overdue):
            return
        with self._lock:
            if self._replacing or not self.running:
                return
            self._replacing = True
        threading.Thread(target=self._replace, name="kaleido-replace", daemon=True).start()

    def _replace(self) -> None:
        """Make before break: open a new browser while the old one goes on drawing, swap
        it in (later exports take it), then close the old one once the drawings it had in
        hand are done (RETIRE_TIMEOUT_S at most). A start that fails leaves the old one."""
        try:
            t0 = time.perf_counter()
            try:
                loop, k = self._open()
            except Exception as exc:  # noqa: BLE001 - keep drawing with the old one
                log.warning("image renderer: a new browser did not start (%r); "
                            "the old one goes on", exc)
                return
            seconds = time.perf_counter() - t0
            with self._lock:
                old_loop, old = self._loop, self._kaleido
                if old is None:                      # closed meanwhile: nothing to replace
                    current = False
                else:
                    self._loop, self._kaleido = loop, k
                    self.replaced += 1
                    self.replace_seconds = seconds
                    current = True
            if not current:
                _close_browser(loop, k)
                return
            log.info("image renderer: browser replaced (%.0f MB over its first reading at "
                     "rest; the new one started in %.1f s)", self.memory.growth_mb(), seconds)
            with self._lock:
                self._drawn.wait_for(lambda: id(old) not in self._inflight, RETIRE_TIMEOUT_S)
            _close_browser(old_loop, old)
        finally:
            with self._lock:
                self._replacing = False

    def _close_if_current(self, k) -> None:
        """Close the browser ``k`` failed on, unless it was replaced meanwhile (then the
        retry draws on the new one and the replacement closes ``k``)."""
        with self._lock:
            if self._kaleido is not k:
                return
        self.close()

    def close(self) -> None:
        with self._lock:
            loop, k = self._loop, self._kaleido
            self._loop = self._kaleido = None
        if k is None:
            return
        _close_browser(loop, k)


def _close_browser(loop: asyncio.AbstractEventLoop, k) -> None:
    """Close kaleido's browser ``k`` and stop its loop."""
    try:
        asyncio.run_coroutine_threadsafe(k.close(), loop).result(10)
    except Exception:  # noqa: BLE001 - closing a browser that already died
        pass
    loop.call_soon_threadsafe(loop.stop)


async def _calc_fig(k, figure: dict, opts: dict) -> bytes:
    """kaleido's calc_fig, then the finished event tasks forgotten (on the loop's thread,
    the only one that touches them)."""
    try:
        return await k.calc_fig(figure, opts=opts)
    finally:
        forget_finished_event_tasks(k)


def forget_finished_event_tasks(k) -> int:
    """Drop the finished tasks choreographer keeps for the browser's event callbacks; how
    many were dropped. choreographer 1.4 (kaleido 1.x) adds a task per subscribed event
    (kaleido subscribes to Page.lifecycleEvent: ~10 per image) to
    ``Broker._background_tasks_cancellable`` and never removes it, so every export left
    ~10 finished tasks in the server for good: measured in-process (tracemalloc, soak.py's
    mix), +1.9 MB and +2 800 tasks after ~240 PNG exports, ~8 kB an export. The set exists
    to cancel running callbacks at close; a finished one needs no cancelling. A choreographer
    without that set is left alone (0)."""
    tasks = getattr(getattr(k, "_broker", None), "_background_tasks_cancellable", None)
    if not isinstance(tasks, set):
        return 0
    done = {t for t in tasks if t.done()}
    tasks.difference_update(done)
    return len(done)


def _wait_seconds() -> tuple[float, bool]:
    """(seconds a render may be waited for, whether the request's time budget sets it):
    WAIT_TIMEOUT_S, or what is left of BRDF_MAX_SECONDS when less, so that an image whose
    figure took most of the budget (or that queued for the tab) ends with the request."""
    b = budget.current()
    left = float("inf") if b is None else b.seconds - b.elapsed()
    return (max(left, 0.0), True) if left < WAIT_TIMEOUT_S else (WAIT_TIMEOUT_S, False)


def _past_budget() -> Busy:
    b = budget.current()
    return Busy(f"the image was not drawn within the time budget (BRDF_MAX_SECONDS="
                f"{b.seconds:g}): retry, or ask for a smaller figure", retry_after=EXPORT_SECONDS,
                what="image export")


_renderer: ImageRenderer | None = None
_renderer_lock = threading.Lock()


def get_renderer() -> ImageRenderer:
    """The process's renderer (a FastAPI dependency; tests override it)."""
    global _renderer
    with _renderer_lock:
        if _renderer is None:
            _renderer = ImageRenderer(environment().chromium or None)
            atexit.register(_renderer.close)
        return _renderer
