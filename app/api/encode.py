"""JSON out: arrays to lists, a divergence (±inf) to null, encoded once."""
from __future__ import annotations

import json

from fastapi import Response

from ..export.jsonable import jsonable


def json_response(payload, status_code: int = 200) -> Response:
    body = json.dumps(jsonable(payload), allow_nan=False, separators=(",", ":"))
    return Response(body, status_code=status_code, media_type="application/json")
