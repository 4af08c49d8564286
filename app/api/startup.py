"""What ``brdf-explorer serve`` has uvicorn serve: the port accepts at once.

uvicorn listens only once its application is imported and started, and importing this
one (numpy, scipy, FastAPI, pydantic's models of every view and route) took 3-12 s of a
cold start while the browser waited on a closed port. :class:`Starting` is imported in a
fraction of a second: it imports the application (app.main:app) in a background thread
and runs its start-up, and meanwhile answers the page's own files (``/``, ``/static/…``:
HTML, scripts, plotly.min.js) through the application's HTTP layers, so the browser
loads and parses them while the server imports; any other request waits until the
application is ready. The log says when it is, and how long it took.
"""
from __future__ import annotations

import asyncio
import importlib
import logging
import os
import signal
import sys
import time

from .. import server
from ..server import page_files

log = logging.getLogger("uvicorn.error")   # uvicorn shows its own loggers' lines
#: the switch interval while the application is imported in the background: the event
#: loop waits at most this long for the GIL to answer a file (Python's default is 5 ms)
IMPORT_SWITCH_INTERVAL = 0.0005


def _file_stack():
    """The page's files behind the application's HTTP layers (the request guard aside:
    it judges query strings and bodies, and these requests have neither)."""
    from starlette.responses import FileResponse
    from starlette.routing import Mount, Route, Router
    from starlette.staticfiles import StaticFiles

    from ..config import Settings
    from ..resources import static_dir
    from .http import wrap_outer
    root = static_dir()
    files = page_files(root)

    def route(path, media_type):
        return lambda request: FileResponse(path, media_type=media_type)
    router = Router([*(Route(url, route(*f)) for url, f in files.items()),
                     Mount("/static", app=StaticFiles(directory=root))])
    served = root.resolve()

    def serves(scope) -> bool:
        """A GET of one of the page's files, with no query string."""
        if scope["method"] not in ("GET", "HEAD") or scope.get("query_string") or scope.get("root_path"):
            return False
        path = scope["path"]
        if path in files:
            return True
        if not path.startswith("/static/") or path.startswith("/static/vendor/"):
            return False
        target = (root / path.removeprefix("/static/")).resolve()
        return target.is_relative_to(served) and target.is_file()
    return serves, wrap_outer(router, Settings.from_env(), root)


class Starting:
    """The ASGI application uvicorn serves: ``target`` (``module:attribute``) imported in
    a background thread and started (its lifespan run), the page's files answered
    meanwhile, every other request held until it is ready (see the module's docstring)."""

    def __init__(self, target: str = "app.main:app", stop=None):
        self.target = target
        #: what stops the server when the application fails to start (uvicorn's SIGTERM)
        self.stop = stop or (lambda: os.kill(os.getpid(), signal.SIGTERM))
        self.app = None                    # the application, once started
        self.failed: str | None = None
        self._ready: asyncio.Event | None = None
        self._files = None
        self._lifespan_in: asyncio.Queue | None = None
        self._lifespan_out: asyncio.Queue | None = None
        self._tasks: set = set()

    async def __call__(self, scope, receive, send):
        if self.app is not None and scope["type"] != "lifespan":
            await self.app(scope, receive, send)
        elif scope["type"] == "lifespan":
            await self._lifespan(scope, receive, send)
        elif scope["type"] == "http" and self._files is not None and self._files[0](scope):
            await self._files[1](scope, receive, send)
        else:
            if self._ready is None:        # served without a lifespan: start now
                self._begin({})
            await self._ready.wait()
            if self.app is None:
                await _unavailable(scope, send, self.failed)
                return
            await self.app(scope, receive, send)

    def _begin(self, state: dict) -> None:
        self._ready = asyncio.Event()
        task = asyncio.get_running_loop().create_task(self._start(state))
        self._tasks.add(task)

    async def _lifespan(self, scope, receive, send) -> None:
        await receive()                                        # lifespan.startup
        self._files = _file_stack()
        self._begin(scope.get("state", {}))
        await send({"type": "lifespan.startup.complete"})
        await receive()                                        # lifespan.shutdown
        await self._ready.wait()
        if self.app is not None and self._lifespan_in is not None:
            await self._lifespan_in.put({"type": "lifespan.shutdown"})
            await self._lifespan_out.get()
        await send({"type": "lifespan.shutdown.complete"})

    async def _start(self, state: dict) -> None:
        t0 = time.perf_counter()
        loop = asyncio.get_running_loop()
        try:
            app = await loop.run_in_executor(None, _import, self.target)
            t_import = time.perf_counter() - t0
            self._lifespan_in, self._lifespan_out = asyncio.Queue(), asyncio.Queue()
            lifespan = {"type": "lifespan", "asgi": {"version": "3.0", "spec_version": "2.0"},
                        "state": state}
            task = loop.create_task(app(lifespan, self._lifespan_in.get, self._lifespan_out.put))
            self._tasks.add(task)
            await self._lifespan_in.put({"type": "lifespan.startup"})
            answer = await self._lifespan_out.get()
            if answer["type"] != "lifespan.startup.complete":
                raise RuntimeError(answer.get("message") or answer["type"])
            self.app = app
            log.info("application ready %.1f s after start-up began (imported in %.1f s); "
                     "until then only the page's files were answered", time.perf_counter() - t0,
                     t_import)
        except Exception as exc:           # the server cannot answer: stop it, as uvicorn would
            self.failed = server.failed = f"{type(exc).__name__}: {exc}"
            log.exception("application failed to start: stopping the server")
            self.stop()
        finally:
            self._ready.set()


def _import(target: str):
    """``module:attribute`` imported with a short GIL switch interval (the event loop
    answers the page's files meanwhile)."""
    module, _, attribute = target.partition(":")
    before = sys.getswitchinterval()
    sys.setswitchinterval(IMPORT_SWITCH_INTERVAL)
    try:
        return getattr(importlib.import_module(module), attribute)
    finally:
        sys.setswitchinterval(before)


async def _unavailable(scope, send, reason: str | None) -> None:
    if scope["type"] != "http":
        return
    await send({"type": "http.response.start", "status": 503,
                "headers": [(b"content-type", b"application/json"), (b"cache-control", b"no-store")]})
    await send({"type": "http.response.body",
                "body": b'{"detail":"the application failed to start: see the server log"}'})


app = Starting()
