"""Input judged before any route sees it: strict numbers in query strings and JSON bodies,
duplicate JSON keys, list lengths, a body parsed off the event loop.

Python's float() reads ``1_0`` as 10; JSON ``true`` and ``"0.3"`` pass for numbers in a
lax schema; a JSON object with a key twice keeps the last silently; NaN and Infinity are
not JSON; a body nested ~1000 deep stops Python's parser with a RecursionError.
Each is a 422 naming the parameter (its path in the body: ``["body", "theta_i_deg", 3]``) (a list longer than BRDF_MAX_BATCH a 413), found
here with the operation's OpenAPI description, so new endpoints are covered as added.
A body is parsed in a worker thread: a 24 MB body took 5 s on the event loop before its
lists were counted, and four at once stalled the worker.
"""
from __future__ import annotations

import json
import re
import sys

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


class _NonFinite:
    """What the parser makes of ``NaN``, ``Infinity`` or ``-Infinity`` (not JSON: RFC 8259
    §6): kept as a marker until the walk knows which field holds it."""

    __slots__ = ("name",)

    def __init__(self, name: str):
        self.name = name


#: levels of arrays and objects a body may nest. The deepest body any operation reads is a
#: LUT's {"values": [i][j][c]} (4 levels); Python's parser stops with a RecursionError near
#: 1000 (sys.getrecursionlimit()), which was a 500.
MAX_JSON_DEPTH = 32


def _too_deep(depth: str) -> Refusal:
    return Refusal(422, ["body"], f"the JSON body nests arrays and objects {depth} levels deep; "
                   f"the limit is {MAX_JSON_DEPTH} (no operation reads more than 4)", "json_too_deep")


def _where(path: tuple) -> str:
    """``models[0].alpha`` for the path ("models", 0, "alpha")."""
    out = ""
    for part in path:
        out += f"[{part}]" if isinstance(part, int) else (f".{part}" if out else str(part))
    return out or "the body"


def parse_json(body: bytes, numeric: frozenset[str], max_list: int) -> None:
    """Refuse a body that is strict JSON's no (duplicate keys, NaN/Infinity), nests deeper
    than MAX_JSON_DEPTH, has a boolean or a string where a number belongs, or a list
    longer than ``max_list``; each refusal locates the field (``["body", "theta_i_deg", 3]``).
    Meant for a worker thread; the route parses the same bytes again when they pass."""
    try:
        value = json.loads(body, object_pairs_hook=_no_duplicates, parse_constant=_NonFinite)
    except RecursionError:
        raise _too_deep(f"about {sys.getrecursionlimit()}") from None
    except ValueError:
        return            # not JSON at all: the route's own 400 says so
    stack = [(value, None, ())]
    while stack:
        node, key, path = stack.pop()
        if len(path) > MAX_JSON_DEPTH:
            raise _too_deep(f"more than {MAX_JSON_DEPTH}")
        if isinstance(node, dict):
            for k, v in node.items():
                _visit(v, k, (*path, k), stack, numeric)
        elif isinstance(node, list):
            if len(node) > max_list:
                raise Refusal(413, ["body", *path], f"{_where(path)} has {len(node)} values; "
                              f"the limit is {max_list} (setting BRDF_MAX_BATCH)", "too_long")
            for i, v in enumerate(node):
                if type(v) is float or type(v) is int:      # the bulk of a large body
                    continue
                _visit(v, key, (*path, i), stack, numeric)


def _visit(v, key, path: tuple, stack: list, numeric: frozenset[str]) -> None:
    """Judge a leaf at ``path`` (under the object key ``key``), or queue a container."""
    if isinstance(v, (dict, list)):
        stack.append((v, key, path))
    elif isinstance(v, _NonFinite):
        raise Refusal(422, ["body", *path], f"{_where(path)}: {v.name} is not a JSON number: "
                      "give a finite number", "finite_number")
    elif key in numeric and isinstance(v, bool):
        raise Refusal(422, ["body", *path], f"{_where(path)}: {str(v).lower()} is not a number",
                      "float_type")
    elif key in numeric and isinstance(v, str) and path[0] == key:
        # a field of the body's own model: JSON has numbers of its own, so "0.3" is a
        # string. Not inside a free-form object (a compared model, a fit's model), which
        # is read as a query is, from strings.
        raise Refusal(422, ["body", *path], f"{_where(path)}: {v!r} is a string; write the number "
                      "without quotes", "float_type")
