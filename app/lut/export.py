"""A quantised LUT as a file: PNG, CSV, C header, GLSL/HLSL array, raw float16 + side-car.

Every file says (in its header, comments or side-car) the kind, the axes and which way
they run, the channels and the quantisation, so that the table is never "flipped" by
guesswork. Layout everywhere: row-major, axes[0] slowest, channel fastest.
"""
from __future__ import annotations

import io
import json
import zipfile

import numpy as np

from ..errors import ParameterError
from . import png

FORMATS = ("json", "png", "csv", "c", "glsl", "hlsl", "f16")
MEDIA = {"png": "image/png", "csv": "text/csv; charset=utf-8", "c": "text/x-c; charset=utf-8",
         "glsl": "text/plain; charset=utf-8", "hlsl": "text/plain; charset=utf-8", "f16": "application/zip"}
EXTENSIONS = {"png": "png", "csv": "csv", "c": "h", "glsl": "glsl", "hlsl": "hlsl", "f16": "zip"}


def describe(meta: dict) -> list[str]:
    axes = "; ".join(f"axes[{k}] = {a['name']} ({len(a['values'])} texel centres (i + 0.5)/n)"
                     for k, a in enumerate(meta["axes"]))
    return [f"BRDF Lobe Explorer LUT: kind={meta['kind']}, model {meta['model_query']}",
            f"built for: {meta['model_label']}",
            f"{axes}; channels {', '.join(meta['channels'])}; quantisation {meta['quantisation']}",
            meta["orientation"], f"usage: {meta['usage']}",
            f"max error after quantisation and bilinear lookup: "
            + ", ".join(f"{c} {e:.2e}" for c, e in zip(meta["channels"], meta["lookup_max"]))]


def _integers(values: np.ndarray, quantisation: str) -> np.ndarray:
    scale = {"unorm8": 255.0, "unorm16": 65535.0}[quantisation]
    return np.round(np.clip(values, 0.0, 1.0) * scale).astype(np.int64)


def _grid(values: np.ndarray) -> np.ndarray:
    """(rows, columns, channels): a 1-D table is one row."""
    return values[None, ...] if values.ndim == 2 else values


def check_format(fmt: str, q: str) -> None:
    """Refuse a file format that cannot hold the quantisation asked (before any work)."""
    if fmt not in FORMATS:
        raise ParameterError("format", f"format must be one of {', '.join(FORMATS)}; got {fmt!r}")
    if fmt == "png" and q not in ("unorm8", "unorm16"):
        raise ParameterError("format", f"format=png stores unsigned normalised integers: give "
                                       f"quantisation=unorm8 or unorm16, not {q}")
    if fmt == "f16" and q != "float16":
        raise ParameterError("format", f"format=f16 stores float16: give quantisation=float16, not {q}")


def render(fmt: str, values: np.ndarray, meta: dict) -> bytes:
    q = meta["quantisation"]
    check_format(fmt, q)
    lines = describe(meta)
    if fmt == "png":
        grid = _integers(_grid(values), q)
        if grid.shape[-1] == 2:                                   # RG in an RGB image, B = 0
            grid = np.concatenate([grid, np.zeros(grid.shape[:-1] + (1,), np.int64)], axis=-1)
        return png.write(grid, 8 if q == "unorm8" else 16,
                         text={"Title": f"BRDF Lobe Explorer LUT {meta['kind']}", "Description": "\n".join(lines),
                               "BRDF-model": meta["model_query"], "BRDF-model-label": meta["model_label"]})
    if fmt == "csv":
        return _csv(values, meta, lines).encode()
    if fmt in ("c", "glsl", "hlsl"):
        return _source(fmt, values, meta, lines).encode()
    if fmt == "f16":
        buf = io.BytesIO()
        side = {k: meta[k] for k in ("kind", "model_query", "model_label", "channels", "orientation", "usage")}
        side.update({"dtype": "float16", "byte_order": "little", "shape": list(values.shape),
                     "layout": "row-major, axes[0] slowest, channel fastest",
                     "axes": [{"name": a["name"], "values": list(map(float, a["values"]))} for a in meta["axes"]]})
        with zipfile.ZipFile(buf, "w", zipfile.ZIP_DEFLATED) as z:
            z.writestr("lut.f16", values.astype("<f2").tobytes())
            z.writestr("lut.json", json.dumps(side, indent=1))
        return buf.getvalue()
    raise AssertionError(f"check_format let format={fmt!r} through")


def _csv(values: np.ndarray, meta: dict, lines: list[str]) -> str:
    names = [a["name"] for a in meta["axes"]]
    out = [f"# {line}" for line in lines]
    out.append(",".join([f"i_{n}" for n in names] + names + list(meta["channels"])))
    for index in np.ndindex(values.shape[:-1]):
        coords = [f"{meta['axes'][k]['values'][i]:.9g}" for k, i in enumerate(index)]
        out.append(",".join([str(i) for i in index] + coords + [f"{x:.9g}" for x in values[index]]))
    return "\n".join(out) + "\n"


def _source(fmt: str, values: np.ndarray, meta: dict, lines: list[str]) -> str:
    q = meta["quantisation"]
    name = f"LUT_{meta['kind'].upper()}"
    dims = "".join(f"[{d}]" for d in values.shape)
    flat = values.ravel()
    if fmt == "c" and q in ("unorm8", "unorm16"):
        ctype, items = ("uint8_t" if q == "unorm8" else "uint16_t"), [str(x) for x in _integers(flat, q)]
        note = f"unsigned normalised: divide by {255 if q == 'unorm8' else 65535}"
    elif fmt == "c" and q == "float16":
        ctype, items = "uint16_t", [f"0x{x:04x}" for x in flat.astype("<f2").view(np.uint16)]
        note = "IEEE 754 binary16 bit patterns"
    else:
        ctype, items, note = "float", [f"{x:.9g}" for x in flat], f"{q} values as decimal floats"
    items = [x if (fmt == "c" and ctype != "float") or "." in x or "e" in x else x + ".0" for x in items]
    body = ",\n".join("    " + ", ".join(items[k:k + 8]) for k in range(0, len(items), 8))
    head = [f"// {line}" for line in lines] + [f"// {note}; row-major {dims}"]
    if fmt == "c":
        return "\n".join(head + ["#include <stdint.h>", f"static const {ctype} {name}{dims} = {{", body, "};"]) + "\n"
    n = flat.size
    if fmt == "glsl":
        return "\n".join(head + [f"const float {name}[{n}] = float[{n}](", body, ");"]) + "\n"
    return "\n".join(head + [f"static const float {name}[{n}] = {{", body, "};"]) + "\n"
