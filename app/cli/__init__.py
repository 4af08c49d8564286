"""``brdf-explorer``: the explorer from a terminal, one command per capability.

The commands come from what the product already declares: ``export`` takes every view
(figure) with that view's own options; every GET operation of the REST API that needs
only its query parameters (``code``, ``lut``, ``conventions``, ``materials``, …) is a
command with the same options (``operations.py``); ``datasets`` and ``fit`` take a file
where the API takes an upload. Options are spelled like the API's query parameters with
dashes (``--theta-i-deg 40``). Nothing here computes: each command calls the function
its API route calls, or the route's own function.
"""
from __future__ import annotations

import os
import sys
from dataclasses import dataclass
from typing import Callable

from . import data, exports, serve
from .options import UsageError


@dataclass(frozen=True)
class Command:
    name: str
    summary: str
    run: Callable[[list[str]], int]


FIXED = (
    Command("serve", serve.SUMMARY, serve.run),
    Command("export", "write one figure (any view) as SVG, PNG, HTML, CSV or JSON", exports.export),
    Command("export-batch", "write a deck of figures, one 'KIND options -o FILE' a line, with one browser",
            exports.batch),
    Command("export-gallery", "write every gallery figure into a directory", exports.gallery),
    Command("figures", "list the figure kinds export writes", exports.figures),
    Command("datasets", data.DATASETS, data.datasets),
    Command("fit", data.FIT, data.fit),
)


def commands() -> dict[str, Command]:
    """Every command: the fixed ones, then one per query-only API operation."""
    from . import operations
    out = {c.name: c for c in FIXED}
    for name, op in operations.operations().items():
        out.setdefault(name, Command(name, f"{op.summary} (GET {op.path})",
                                     lambda argv, op=op: operations.run(op, argv)))
    return out


def usage(found: dict[str, Command]) -> str:
    width = max(map(len, found))
    lines = ["usage: brdf-explorer COMMAND [options]   (brdf-explorer COMMAND --help: its options)",
             "", "Serve the explorer, or use its capabilities with no server running.", "", "commands:"]
    lines += [f"  {c.name:<{width}}  {c.summary}" for c in found.values()]
    lines += ["", "Examples:",
              "  brdf-explorer serve --port 8000",
              "  brdf-explorer export lobe --alpha 0.3 --theta-i-deg 40 -o lobe.svg",
              "  brdf-explorer code --ndf beckmann --lang hlsl -o brdf.hlsl",
              "  brdf-explorer conventions --roughness 0.5"]
    return "\n".join(lines)


def main(argv: list[str] | None = None) -> int:
    argv = list(sys.argv[1:] if argv is None else argv)
    if not argv or argv[0] in ("-h", "--help", "help"):
        print(usage(commands()))
        return 0 if argv else 2
    name = argv[0]
    found = {c.name: c for c in FIXED}
    if name not in found:
        found = commands()                  # reads the app's routes: only when needed
    if name not in found:
        print(f"brdf-explorer: unknown command {name!r}\n\n{usage(found)}", file=sys.stderr)
        return 2
    try:
        return found[name].run(argv[1:])
    except UsageError as e:
        print(f"brdf-explorer {name}: {e}", file=sys.stderr)
        return 2
    except BrokenPipeError:
        # the reader stopped early (``| head``): what it read is what it wanted. Standard
        # output goes to /dev/null so that the interpreter's last flush does not fail too.
        os.dup2(os.open(os.devnull, os.O_WRONLY), sys.stdout.fileno())
        return 0
