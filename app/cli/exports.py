"""Figures out of the explorer with no server running: ``export`` (one figure),
``export-batch`` (a deck, one browser), ``export-gallery`` (every gallery figure) and
``figures`` (the kinds there are). Every view is a kind; its options are its query's."""
from __future__ import annotations

import argparse
import shlex
import sys
import time
from pathlib import Path

from .options import UsageError, add_fields, add_mkdir, check_directory, given, option, validate
from .progress import Progress

FORMATS = ("Formats by suffix: .svg .png (Chromium), .html (standalone), .csv, "
           ".json (data), .plotly.json (figure).")


def _export_parser(kind: str):
    from ..export import build
    from ..views import VIEWS
    view = VIEWS[kind]
    model = build.image_query(view)
    parser = argparse.ArgumentParser(prog=f"brdf-explorer export {kind}", description=view.summary,
                                     allow_abbrev=False, epilog=FORMATS)
    parser.add_argument("-o", "--output", required=True, type=Path, help="file to write")
    add_mkdir(parser)
    add_fields(parser, model)
    return view, model, parser


def parse_export(argv: list[str], mkdir: bool = False):
    """``KIND options -o FILE`` → (view, validated query, output path)."""
    from ..views import VIEWS
    if not argv or argv[0] in ("-h", "--help"):
        print("usage: brdf-explorer export KIND [options] -o FILE [--mkdir]\n"
              f"KIND is one of: {', '.join(VIEWS)}\n"
              "brdf-explorer export KIND --help lists the options of a figure\n" + FORMATS)
        raise SystemExit(0)
    kind = argv[0]
    if kind not in VIEWS:
        raise UsageError(f"unknown figure kind {kind!r}; one of {', '.join(VIEWS)}")
    view, model, parser = _export_parser(kind)
    args = parser.parse_args(argv[1:])
    q = validate(model, given(args, model))
    check_directory(args.output, mkdir or args.mkdir)
    return view, q, args.output


def run_exports(jobs: list[list[str]], quiet: bool = False, mkdir: bool = False) -> int:
    """Run export command lines (each ``KIND options -o FILE``) with one browser; every
    line is checked before the first file is written."""
    from ..config import Settings
    from ..errors import ParameterError
    from ..export import files
    from ..export.image import ExportUnavailable, ImageRenderer

    parsed = []
    for i, argv in enumerate(jobs, 1):
        try:
            view, q, out = parse_export(argv, mkdir)
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


def export(argv: list[str]) -> int:
    return run_exports([argv])


def batch(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(
        prog="brdf-explorer export-batch",
        description="Export many figures with one browser: each line of DECK is "
                    "'KIND options -o FILE' (blank lines and # comments skipped).")
    parser.add_argument("deck", type=Path)
    parser.add_argument("-q", "--quiet", action="store_true")
    add_mkdir(parser)
    args = parser.parse_args(argv)
    jobs = [shlex.split(line, comments=True) for line in args.deck.read_text().splitlines()]
    return run_exports([j for j in jobs if j], quiet=args.quiet, mkdir=args.mkdir)


def gallery(argv: list[str]) -> int:
    parser = argparse.ArgumentParser(prog="brdf-explorer export-gallery",
                                     description="Export every gallery figure into DIR.")
    parser.add_argument("directory", type=Path)
    parser.add_argument("--formats", default="svg", help="comma-separated: svg,png,html,csv,json")
    parser.add_argument("-q", "--quiet", action="store_true")
    add_mkdir(parser)
    args = parser.parse_args(argv)
    check_directory(args.directory / "x", args.mkdir)
    from ..gallery import available
    from ..views import VIEWS
    jobs = []
    # the views' figures; the other cards (data set, fit, code, LUT, conventions) are not
    # a view's export, and their files are their API links
    for entry in (e for e in available() if e["kind"] in VIEWS):
        for fmt in args.formats.split(","):
            argv_job = [entry["kind"]]
            for k, v in entry["state"].items():
                if isinstance(v, bool):
                    argv_job.append(option(k) if v else "--no-" + k.replace("_", "-"))
                else:
                    argv_job += [option(k), str(v)]
            jobs.append(argv_job + ["-o", str(args.directory / f"{entry['id']}.{fmt.strip()}")])
    return run_exports(jobs, quiet=args.quiet)


def figures(argv: list[str]) -> int:
    """The figure kinds, one a line: name, title, what it shows."""
    argparse.ArgumentParser(prog="brdf-explorer figures",
                            description="List the figure kinds (views) that export writes.").parse_args(argv)
    from ..views import VIEWS
    width = max(map(len, VIEWS))
    for name, view in VIEWS.items():
        print(f"{name:<{width}}  {view.title}: {view.summary}")
    print("\nbrdf-explorer export KIND --help lists a kind's options; " + FORMATS)
    return 0
