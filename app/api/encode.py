"""JSON out: arrays to lists, a divergence (±inf) to null, encoded once."""
from __future__ import annotations

import json

import numpy as np
from fastapi import Response


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


def json_response(payload, status_code: int = 200) -> Response:
    body = json.dumps(jsonable(payload), allow_nan=False, separators=(",", ":"))
    return Response(body, status_code=status_code, media_type="application/json")
