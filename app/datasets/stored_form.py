"""A data set as the two files a shared store keeps, and back: ``meta`` (JSON: the class,
format, channels or terms, size) and the ``.npz`` bytes of its arrays. Exact both ways,
so a data set read back on another worker or after a restart is the one uploaded."""
from __future__ import annotations

import io

import numpy as np

from .. import npz
from .dataset import BrdfData, TermData

#: the arrays of a BRDF data set that may be present (a MERL table, or sampled directions)
BRDF_ARRAYS = ("table", "l", "v", "f")


def encode(data) -> tuple[dict, bytes]:
    """(meta, .npz bytes) of a data set, to rebuild it exactly."""
    if isinstance(data, TermData):
        meta = {"class": "term", "format": data.format, "axis": data.axis, "size": data.size,
                "terms": list(data.terms)}
        arrays = {"x": data.x, **{f"term_{k}": v for k, v in data.terms.items()}}
    else:
        meta = {"class": "brdf", "format": data.format, "channels": list(data.channels),
                "size": data.size}
        arrays = {k: getattr(data, k) for k in BRDF_ARRAYS if getattr(data, k) is not None}
    buffer = io.BytesIO()
    np.savez(buffer, **arrays)
    return meta, buffer.getvalue()


def decode(meta: dict, content: bytes):
    """The data set of ``encode``'s (meta, bytes). Raises ValueError, KeyError or
    zipfile.BadZipFile for damaged content."""
    arrays = npz.read(io.BytesIO(content))
    if meta["class"] == "term":
        return TermData(meta["format"], meta["axis"], arrays["x"],
                        {k: arrays[f"term_{k}"] for k in meta["terms"]}, meta["size"])
    return BrdfData(meta["format"], tuple(meta["channels"]), meta["size"],
                    **{k: arrays[k] for k in BRDF_ARRAYS if k in arrays})
