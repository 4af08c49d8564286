"""``brdf-explorer``: serve the explorer, or export figures with no server running.

    brdf-explorer serve [--host --port --workers]
    brdf-explorer export KIND [model and view options] -o FILE.{svg,png,html,csv,json}
    brdf-explorer export-batch DECK.txt       (one ``KIND options -o FILE`` per line)
    brdf-explorer export-gallery DIR [--formats svg,png,csv]

Options are spelled like the API's query parameters with dashes: ``--ndf ggx --alpha 0.3
--theta-i-deg 40 --log``; ``brdf-explorer export KIND --help`` lists those of a view.
Image exports share one headless Chromium for the whole run.
"""
from __future__ import annotations

import argparse
import shlex
import sys
import time
from pathlib import Path


def _serve(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="brdf-explorer serve", description="start the web explorer and REST API")
    parser.add_argument("--host", default="127.0.0.1")
    parser.add_argument("--port", type=int, default=8000)
    parser.add_argument("--workers", type=int, default=1,
                        help="worker processes; the service is stateless, so N workers scale")
    parser.add_argument("--reload", action="store_true", help="restart on code changes (development)")
    args = parser.parse_args(argv)
    import uvicorn

    from . import server
    # server.APP accepts at once and imports the application (app.main:app) behind it
    uvicorn.run(server.APP, host=args.host, port=args.port, http=server.HTTP_PROTOCOL,
                workers=None if args.reload else args.workers, reload=args.reload,
                timeout_worker_healthcheck=server.WORKER_HEALTHCHECK_S)
    return 1 if server.failed else 0


# ------------------------------------------------------------------ export ------
class UsageError(Exception):
    """Bad command line (exit status 2)."""


def _option(name: str) -> str:
    return "--" + name.replace("_", "-")


def _export_parser(kind: str):
    from .export import build
    from .views import VIEWS
    view = VIEWS[kind]
    model = build.image_query(view)
    parser = argparse.ArgumentParser(
        prog=f"brdf-explorer export {kind}", description=view.summary, allow_abbrev=False,
        epilog="Formats by suffix: .svg .png (Chromium), .html (standalone), .csv, "
               ".json (data), .plotly.json (figure).")
    parser.add_argument("-o", "--output", required=True, type=Path, help="file to write")
    for name, field in model.model_fields.items():
        help_text = (field.description or "").replace("%", "%%")
        default = field.default
        if field.annotation is bool:
            parser.add_argument(_option(name), dest=name, action=argparse.BooleanOptionalAction,
                                default=None, help=f"{help_text} (default {default})")
        else:
            shown = "" if default is None else f" (default {default})"
            parser.add_argument(_option(name), dest=name, default=None, metavar="VALUE",
                                help=help_text + shown)
    return view, model, parser


def parse_export(argv: list[str]):
    """``KIND options -o FILE`` → (view, validated query, output path)."""
    from pydantic import ValidationError
    from .views import VIEWS
    if not argv or argv[0] in ("-h", "--help"):
        raise UsageError("usage: brdf-explorer export KIND [options] -o FILE\n"
                         f"KIND is one of: {', '.join(VIEWS)}\n"
                         "brdf-explorer export KIND --help lists the options of a figure")
    kind = argv[0]
    if kind not in VIEWS:
        raise UsageError(f"unknown figure kind {kind!r}; one of {', '.join(VIEWS)}")
    view, model, parser = _export_parser(kind)
    args = parser.parse_args(argv[1:])
    given = {k: v for k, v in vars(args).items() if k != "output" and v is not None}
    try:
        q = model.model_validate(given)
    except ValidationError as e:
        lines = [f"{_option(str(err['loc'][0]))}: {err['msg']}" for err in e.errors()]
        raise UsageError("\n".join(lines)) from None
    return view, q, args.output


class Progress:
    """A one-line progress bar on stderr (redrawn in place on a terminal, one line per
    step otherwise)."""

    WIDTH = 28

    def __init__(self, total: int, stream=None):
        self.total, self.done, self.stream = total, 0, stream or sys.stderr
        self.t0 = time.perf_counter()
        self.tty = hasattr(self.stream, "isatty") and self.stream.isatty()

    def step(self, label: str) -> None:
        self.done += 1
        filled = round(self.WIDTH * self.done / max(self.total, 1))
        bar = "#" * filled + "." * (self.WIDTH - filled)
        elapsed = time.perf_counter() - self.t0
        line = f"[{bar}] {self.done}/{self.total} {elapsed:5.1f} s  {label}"
        if self.tty:
            self.stream.write("\r\033[K" + line + ("\n" if self.done == self.total else ""))
        else:
            self.stream.write(line + "\n")
        self.stream.flush()


def run_exports(jobs: list[list[str]], quiet: bool = False) -> int:
    """Run export command lines (each ``KIND options -o FILE``) with one browser."""
    from .errors import ParameterError
    from .config import Settings
    from .export import files
    from .export.image import ExportUnavailable, ImageRenderer

    parsed = []
    for i, argv in enumerate(jobs, 1):
        try:
            view, q, out = parse_export(argv)
            files.format_of(out)
        except (UsageError, ValueError) as e:
            prefix = f"job {i} ({' '.join(argv)}): " if len(jobs) > 1 else ""
            print(f"brdf-explorer export: {prefix}{e}", file=sys.stderr)
            return 2
        parsed.append((view, q, out))
    settings = Settings.from_env()
    renderer = ImageRenderer(settings.chromium or None)
    progress = Progress(len(parsed)) if (len(parsed) > 1 and not quiet) else None
    try:
        for view, q, out in parsed:
            t0 = time.perf_counter()
            try:
                size = files.write(view, q, out, settings, renderer)
            except ParameterError as e:
                print(f"brdf-explorer export: {out}: {e.message}", file=sys.stderr)
                return 2
            except ExportUnavailable as e:
                print(f"brdf-explorer export: {out}: {e}", file=sys.stderr)
                return 3
            label = f"{out} ({size / 1024:.0f} KiB, {time.perf_counter() - t0:.2f} s)"
            if progress:
                progress.step(label)
            elif not quiet:
                print(f"wrote {label}", file=sys.stderr)
    finally:
        renderer.close()
    return 0


def _batch(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(
        prog="brdf-explorer export-batch",
        description="Export many figures with one browser: each line of DECK is "
                    "'KIND options -o FILE' (blank lines and # comments skipped).")
    parser.add_argument("deck", type=Path)
    parser.add_argument("-q", "--quiet", action="store_true")
    args = parser.parse_args(argv)
    jobs = [shlex.split(line, comments=True) for line in args.deck.read_text().splitlines()]
    return run_exports([j for j in jobs if j], quiet=args.quiet)


def _gallery(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="brdf-explorer export-gallery",
                                     description="Export every gallery figure into DIR.")
    parser.add_argument("directory", type=Path)
    parser.add_argument("--formats", default="svg", help="comma-separated: svg,png,html,csv,json")
    parser.add_argument("-q", "--quiet", action="store_true")
    args = parser.parse_args(argv)
    from .gallery import available
    jobs = []
    for entry in available():
        for fmt in args.formats.split(","):
            argv_job = [entry["kind"]]
            for k, v in entry["state"].items():
                if isinstance(v, bool):
                    argv_job.append(_option(k) if v else "--no-" + k.replace("_", "-"))
                else:
                    argv_job += [_option(k), str(v)]
            jobs.append(argv_job + ["-o", str(args.directory / f"{entry['id']}.{fmt.strip()}")])
    return run_exports(jobs, quiet=args.quiet)


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    commands = {"serve": _serve, "export": lambda a: run_exports([a]),
                "export-batch": _batch, "export-gallery": _gallery}
    if not argv or argv[0] not in commands:
        print(__doc__.strip(), file=sys.stderr)
        return 0 if argv[:1] in (["-h"], ["--help"]) else 2
    try:
        return commands[argv[0]](argv[1:])
    except UsageError as e:
        print(f"brdf-explorer: {e}", file=sys.stderr)
        return 2


if __name__ == "__main__":
    raise SystemExit(main())
