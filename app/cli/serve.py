"""``brdf-explorer serve``: the web explorer and the REST API."""
from __future__ import annotations

import argparse

SUMMARY = "start the explorer and its REST API at http://127.0.0.1:8000"


def run(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="brdf-explorer serve", description=SUMMARY)
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8000)
    parser.add_argument("--workers", type=int, default=1,
                        help="worker processes (they share the cache directory, data sets included), one per core")
    parser.add_argument("--reload", action="store_true", help="restart on code changes (development)")
    parser.add_argument("--timeout-graceful-shutdown", type=float, default=None, metavar="SECONDS",
                        help="after SIGTERM, seconds running requests are given before they are "
                             "cancelled and the heavy pool's workers killed (default: "
                             "BRDF_MAX_SECONDS + 1, the longest a request may take)")
    args = parser.parse_args(argv)
    import uvicorn

    from .. import server
    from ..config import environment
    from ..integrate.cost import GRACE_SECONDS
    graceful = args.timeout_graceful_shutdown
    if graceful is None:
        graceful = environment().max_seconds + GRACE_SECONDS
    # server.APP accepts at once and imports the application (app.main:app) behind it
    uvicorn.run(server.APP, host=args.host, port=args.port, http=server.HTTP_PROTOCOL,
                workers=None if args.reload else args.workers, reload=args.reload,
                timeout_worker_healthcheck=server.WORKER_HEALTHCHECK_S,
                timeout_graceful_shutdown=graceful)
    return 1 if server.failed else 0
