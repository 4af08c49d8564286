"""Input judged before any route sees it: strict numbers in query strings and JSON bodies,
duplicate JSON keys, list lengths, a body parsed off the event loop.

Python's float() reads ``1_0`` as 10 and JSON ``true`` passes for 1 in a lax schema;
a JSON object with a key twice keeps the last silently; NaN and Infinity are not JSON.
Each is a 422 naming the parameter (a list longer than BRDF_MAX_BATCH a 413), found
here with the operation's OpenAPI description, so new endpoints are covered as added.
A body is parsed in a worker thread: a 24 MB body took 5 s on the event loop before its
lists were counted, and four at once stalled the worker.
"""
from __future__ import annotations

import json
import re

#: a number as JSON and the URL forms write it: digits, one '.', an exponent
NUMBER = re.compile(r"[+-]?(\d+\.?\d*|\.\d+)([eE][+-]?\d+)?")


class Refusal(Exception):
    """Input refused before the route: ``status``, ``loc``, ``message``, ``kind``."""

    def __init__(self, status: int, loc: list, message: str, kind: str):
        super().__init__(message)
        self.status, self.loc, self.message, self.kind = status, loc, message, kind


def _is_numeric(schema: dict) -> bool:
    variants = [schema, *schema.get("anyOf", []), *schema.get("oneOf", [])]
    return any(v.get("type") in ("number", "integer")
               or (isinstance(v.get("items"), dict) and _is_numeric(v["items"]))
               for v in variants if isinstance(v, dict))


def numeric_names(document: dict) -> frozenset[str]:
    """Every parameter name that is a number (or a list of numbers) in some operation:
    in a JSON body a value under such a key must be a number, never a boolean."""
    names = set()
    for item in document.get("paths", {}).values():
        for op in item.values():
            if isinstance(op, dict):
                names.update(p["name"] for p in op.get("parameters", [])
                             if _is_numeric(p.get("schema", {})))
    for schema in document.get("components", {}).get("schemas", {}).values():
        names.update(k for k, v in schema.get("properties", {}).items() if _is_numeric(v))
    return frozenset(names)


def check_query(pairs, operation: dict | None) -> None:
    """Numeric query values written as JSON and URLs write numbers (``1_0`` refused;
    ``nan``, ``inf`` and words are left to the schema, which names its bound)."""
    if operation is None:
        return
    numeric = _numeric_query(operation)
    for key, value in pairs:
        if key in numeric and "_" in value:
            for part in value.split(","):
                if part.strip() and not NUMBER.fullmatch(part.strip()):
                    raise Refusal(422, ["query", key], f"{key}={value!r} is not a number: "
                                  "digits, one '.', an optional exponent ('_' is not allowed)",
                                  "float_parsing")


#: id(operation) → (the operation, its numeric query parameters): read once per operation
#: (the figures' ~46 parameters took ~0.1 ms a request); the entry holds the operation,
#: so its id is not reused while the entry lives
_NUMERIC_QUERY: dict[int, tuple[dict, frozenset[str]]] = {}


def _numeric_query(operation: dict) -> frozenset[str]:
    hit = _NUMERIC_QUERY.get(id(operation))
    if hit is None:
        hit = _NUMERIC_QUERY[id(operation)] = (operation, frozenset(
            p["name"] for p in operation.get("parameters", [])
            if p.get("in") == "query" and _is_numeric(p.get("schema", {}))))
    return hit[1]


def _no_duplicates(pairs):
    seen = {}
    for key, value in pairs:
        if key in seen:
            raise Refusal(422, ["body", key], f"{key} is given twice in the JSON object; "
                          "give it once", "duplicate_key")
        seen[key] = value
    return seen


def _constant(name):
    raise Refusal(422, ["body"], f"{name} is not a JSON number: give a finite number",
                  "finite_number")


def parse_json(body: bytes, numeric: frozenset[str], max_list: int) -> None:
    """Refuse a body that is strict JSON's no (duplicate keys, NaN/Infinity), has a
    boolean where a number belongs, or a list longer than ``max_list``. Meant for a
    worker thread; the route parses the same bytes again when they pass."""
    try:
        value = json.loads(body, object_pairs_hook=_no_duplicates, parse_constant=_constant)
    except (ValueError, RecursionError):
        return            # not JSON at all: the route's own 400 says so
    stack = [(value, None)]
    while stack:
        node, key = stack.pop()
        if isinstance(node, dict):
            stack.extend((v, k) for k, v in node.items())
        elif isinstance(node, list):
            if len(node) > max_list:
                raise Refusal(413, ["body", key or ""], f"{key or 'a list'} has {len(node)} "
                              f"values; the limit is {max_list} (setting BRDF_MAX_BATCH)",
                              "too_long")
            stack.extend((v, key) for v in node)
        elif isinstance(node, bool) and key in numeric:
            raise Refusal(422, ["body", key], f"{key}: {str(node).lower()} is not a number",
                          "float_type")
