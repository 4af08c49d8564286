"""``brdf-explorer``: serve the explorer."""
from __future__ import annotations

import argparse


def main(argv: list[str] | None = None) -> int:
    parser = argparse.ArgumentParser(prog="brdf-explorer", description="BRDF Lobe Explorer")
    sub = parser.add_subparsers(dest="command", required=True)
    serve = sub.add_parser("serve", help="start the web explorer and REST API")
    serve.add_argument("--host", default="127.0.0.1")
    serve.add_argument("--port", type=int, default=8000)
    serve.add_argument("--workers", type=int, default=1,
                       help="worker processes; the service is stateless, so N workers scale")
    serve.add_argument("--reload", action="store_true", help="restart on code changes (development)")
    args = parser.parse_args(argv)
    if args.command == "serve":
        import uvicorn
        uvicorn.run("app.main:app", host=args.host, port=args.port,
                    workers=None if args.reload else args.workers, reload=args.reload)
    return 0


if __name__ == "__main__":
    raise SystemExit(main())
