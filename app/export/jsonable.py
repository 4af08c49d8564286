"""Numbers as JSON: arrays to lists, a divergence (±inf) or a gap (NaN) to null."""
from __future__ import annotations

import numpy as np
import orjson

#: orjson's options for every JSON answer: int keys as text, as json.dumps writes them
OPTIONS = orjson.OPT_NON_STR_KEYS


def jsonable(value):
    if isinstance(value, np.ndarray):
        if value.dtype.kind in "fc":
            a = value.astype(float)
            out = a.tolist()
            bad = ~np.isfinite(a)
            if bad.any():
                out = np.where(bad, None, np.asarray(out, dtype=object)).tolist()
            return out
        return value.tolist()
    if isinstance(value, (np.floating, float)):
        return float(value) if np.isfinite(value) else None
    if isinstance(value, np.integer):
        return int(value)
    if isinstance(value, dict):
        return {k: jsonable(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [jsonable(v) for v in value]
    return value


def json_bytes(payload) -> bytes:
    """The JSON text every answer sends (the API's responses, the CLI's output)."""
    return orjson.dumps(jsonable(payload), option=OPTIONS)
