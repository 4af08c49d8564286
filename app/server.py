"""How ``brdf-explorer serve`` runs the app: uvicorn's HTTP protocol with TCP_NODELAY
(and :mod:`app.api.startup` behind it, which accepts at once).

With ``--workers N`` uvicorn binds the listening socket itself with ``proto`` 0, the
accepted sockets inherit it, and asyncio then leaves Nagle's algorithm on (it sets
TCP_NODELAY only for ``proto == IPPROTO_TCP``): every keep-alive response after the
first waited ~40 ms for the client's delayed ACK. Measured with bench/load.sh: 2
workers served 180 requests/s of /api/v1/health against 1 worker's 1000, every request
at 44 ± 2.5 ms. Reported upstream as Kludex/uvicorn#3149; this sets the option on every
accepted connection, whichever path bound the socket.
"""
from __future__ import annotations

import contextlib
import importlib.util
import socket
from pathlib import Path

from uvicorn.protocols.http.auto import AutoHTTPProtocol

#: what ``uvicorn.run(http=...)`` takes (an import string: each worker imports it)
HTTP_PROTOCOL = "app.server:NoDelayHTTPProtocol"


class NoDelayHTTPProtocol(AutoHTTPProtocol):
    def connection_made(self, transport) -> None:
        sock = transport.get_extra_info("socket")
        if sock is not None and sock.family in (socket.AF_INET, socket.AF_INET6):
            with contextlib.suppress(OSError):
                sock.setsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY, 1)
        super().connection_made(transport)


#: Seconds uvicorn's supervisor waits for a worker to answer its health check before it
#: kills and restarts it (uvicorn's default is 5). A worker computing under heavy load
#: answers late but is alive: in the soak (bench/soak.py, load average 20 on 2 cores) a
#: worker was restarted four times (its memory dropped to a fresh process's) with three
#: dropped connections, and no crash in the log: the 5 s check is what restarts a live
#: worker. Three times the longest a request may compute (BRDF_MAX_SECONDS + 1 s).
WORKER_HEALTHCHECK_S = 33


#: what ``brdf-explorer serve`` has uvicorn serve (an import string: each worker imports
#: it): the application behind a start-up layer that accepts at once (app/api/startup.py)
APP = "app.api.startup:app"
#: why the application failed to start, when it did (set by app.api.startup): the exit status
failed: str | None = None


def plotly_js() -> Path:
    """plotly.js of the installed plotly package (found without importing plotly)."""
    origin = importlib.util.find_spec("plotly").origin
    return Path(origin).resolve().parent / "package_data" / "plotly.min.js"


def page_files(static_dir: Path) -> dict[str, tuple[Path, str]]:
    """The page's routes outside /static/: request path → (file, media type)."""
    return {"/": (static_dir / "index.html", "text/html"),
            "/favicon.ico": (static_dir / "favicon.svg", "image/svg+xml"),
            "/static/vendor/plotly.min.js": (plotly_js(), "application/javascript")}
