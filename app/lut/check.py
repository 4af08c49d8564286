"""An uploaded LUT read: a PNG or JSON body to unit-range floats of the kind's shape,
refused (422 naming the body) when it is not one. What the table's conventions are is
inferred in infer.py."""
from __future__ import annotations

import json

import numpy as np

from ..errors import ParameterError
from . import png
from .build import SIZE_MAX, SIZE_MIN

#: JSON nesting accepted: an object holding [i][j][c] is 4 deep; deeper is refused before
#: parsing (a recursive parser would otherwise exhaust its stack on "[[[[…")
MAX_JSON_DEPTH = 8


def json_depth(body: bytes) -> int:
    """The deepest nesting of ``[``/``{`` in ``body``, counting brackets inside strings too
    (an over-estimate only for strings holding brackets, which a LUT body has none of)."""
    raw = np.frombuffer(body, np.uint8)
    step = (np.isin(raw, (ord("["), ord("{"))).astype(np.int64)
            - np.isin(raw, (ord("]"), ord("}"))))
    return int(np.cumsum(step).max(initial=0))


def parse(body: bytes, content_type: str, channels: int, dims: int) -> tuple[np.ndarray, int | None]:
    """The uploaded values as floats [rows][columns][channels] (or [rows][channels]) and
    the PNG's bit depth (None for JSON): a PNG (8 or 16 bits, divided by 2^bits − 1; RG
    tables in R and G) or JSON ``{"values": [i][j][c]}`` (as written)."""
    bits = None
    if body.startswith(png.SIGNATURE) or content_type.startswith("image/png"):
        try:
            samples, bits = png.read(body, max_side=SIZE_MAX)
        except png.PngSizeError as exc:
            raise ParameterError("body", f"{exc}: a LUT is n × n (kc_E_avg: 1 × n) with n in "
                                         f"[{SIZE_MIN}, {SIZE_MAX}]", loc="body") from None
        except png.PngError as exc:
            raise ParameterError("body", f"malformed PNG: {exc}", loc="body") from None
        if samples.shape[-1] < channels:
            raise ParameterError("body", f"the PNG has {samples.shape[-1]} channel(s); this kind has {channels}",
                                 loc="body")
        values = samples[..., :channels] / float(2 ** bits - 1)
        if dims == 1 and values.shape[0] == 1:
            values = values[0]
    else:
        depth = json_depth(body)
        if depth > MAX_JSON_DEPTH:
            raise ParameterError("body", f"the JSON body nests {depth} deep; a LUT is "
                                         f'{{"values": [i][j][c]}}, at most {MAX_JSON_DEPTH} deep',
                                 loc="body")
        try:
            data = json.loads(body)
            values = np.asarray(data["values"] if isinstance(data, dict) else data, dtype=float)
        except (ValueError, KeyError, TypeError):
            raise ParameterError("body", 'the body must be a PNG or JSON {"values": [i][j][c]} of numbers',
                                 loc="body") from None
        if values.ndim == dims:           # one channel given without its own axis
            values = values[..., None]
    n = values.shape[0] if values.ndim else 0
    shape = (n,) * dims + (channels,)
    if values.shape != shape or not SIZE_MIN <= n <= SIZE_MAX:
        raise ParameterError("body", f"the uploaded LUT has shape {list(values.shape)}; this kind needs "
                                     f"{['n'] * dims + [channels]} with n in [{SIZE_MIN}, {SIZE_MAX}] "
                                     "([rows][columns][channels])", loc="body")
    if not np.all(np.isfinite(values)):
        raise ParameterError("body", "the uploaded LUT holds non-finite values", loc="body")
    return values, bits
