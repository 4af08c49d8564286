"""Write one export to a file, the format chosen by the file's suffix.

========================  ==========================================================
``.svg``, ``.png``        the figure as an image (headless Chromium via kaleido)
``.html``                 a standalone page with the figure (plotly.js inlined)
``.csv``                  the numbers behind the figure (see :mod:`app.export.table`)
``.json``                 the data, as ``GET /api/v1/{kind}`` returns it
``.plotly.json``          the Plotly figure, as ``GET /api/v1/figures/{kind}`` returns it
========================  ==========================================================
"""
from __future__ import annotations

import orjson
from pathlib import Path

from pydantic import BaseModel

from ..config import Settings
from ..views import View
from . import build
from .image import ImageRenderer
from .jsonable import jsonable

SUFFIXES = (".svg", ".png", ".html", ".csv", ".plotly.json", ".json")


def format_of(path: Path) -> str:
    name = path.name.lower()
    for suffix in SUFFIXES:
        if name.endswith(suffix):
            return suffix.lstrip(".")
    raise ValueError(f"{path.name}: the file name must end in one of {', '.join(SUFFIXES)}")


def render_bytes(view: View, q: BaseModel, fmt: str, settings: Settings,
                 renderer: ImageRenderer | None) -> bytes:
    """The bytes of one export (``q`` an :func:`build.image_query` instance)."""
    if fmt in ("svg", "png"):
        build.check_image_size(q, settings)
    produced = build.produce(view, q, settings)
    if fmt in ("svg", "png"):
        if renderer is None:
            raise ValueError("an image export needs a renderer")
        return renderer.render(produced.figure, fmt, q.width, q.height, q.scale)
    if fmt == "html":
        return build.standalone_html(produced).encode()
    if fmt == "csv":
        return produced.csv().encode()
    if fmt == "plotly.json":
        return build.figure_json(produced).encode()
    if fmt == "json":
        if produced.vary is None:
            payload = produced.data
        else:
            payload = {"vary": produced.vary,
                       "variants": [{"value": v, "data": d} for v, d in produced.payloads]}
        return orjson.dumps(jsonable(payload), option=orjson.OPT_NON_STR_KEYS)
    raise ValueError(f"unknown format {fmt}")


def write(view: View, q: BaseModel, path: Path, settings: Settings,
          renderer: ImageRenderer | None) -> int:
    """Write the export to ``path`` (format from its suffix); returns the byte count."""
    body = render_bytes(view, q, format_of(path), settings, renderer)
    path.parent.mkdir(parents=True, exist_ok=True)
    path.write_bytes(body)
    return len(body)
