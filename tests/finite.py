"""JSON as the API must send it: no NaN or ±Infinity token (a divergence is null). The
body is parsed, not searched: a figure's base64 arrays can spell "NaN" in their text."""
from __future__ import annotations

import json


def _no_constant(token: str):
    raise AssertionError(f"JSON body contains {token}")


def finite_json(text: str | bytes):
    """The parsed body; fails on a NaN, Infinity or -Infinity token."""
    return json.loads(text, parse_constant=_no_constant)
