"""Each body only in the content types its operation reads (415 otherwise).

The table is the OpenAPI document's: an operation's ``requestBody.content`` lists the
media types it takes (FastAPI writes ``application/json`` for a body model; an upload
route lists its own, as POST /api/v1/datasets does). ``UNDECLARED`` adds the operations
that read their body themselves and do not describe it there yet; when one does, its entry
here is redundant and goes.

A body with no Content-Type is taken (Python's ``requests`` and ``httpx`` send raw bytes
without one, and a browser's foreign write is stopped by its Origin: origin.py). A
``text/plain`` or ``application/x-www-form-urlencoded`` body — what an HTML form or a
preflight-free fetch sends — is refused unless the operation lists it, so a JSON or CSV
upload route cannot be reached with the content types that need no CORS preflight.
"""
from __future__ import annotations

from starlette.datastructures import Headers

from .strict import Refusal

#: (method, path) → media types of operations whose body the OpenAPI does not describe
UNDECLARED: dict[tuple[str, str], tuple[str, ...]] = {}
#: the methods whose body is judged here
BODY_METHODS = frozenset({"POST", "PUT", "PATCH"})


def accepted(operation: dict | None, method: str, path: str) -> tuple[str, ...]:
    """The media types the operation's body may have; () when it declares no body."""
    declared = ((operation or {}).get("requestBody") or {}).get("content", {})
    return tuple(declared) or UNDECLARED.get((method, path), ())


def media_type(headers: Headers) -> str:
    """The Content-Type without its parameters, lower case; '' when absent."""
    return headers.get("content-type", "").split(";")[0].strip().lower()


def refusal(operation: dict | None, method: str, path: str, headers: Headers) -> Refusal | None:
    """A 415 naming the accepted types when the body's type is not among them."""
    if method not in BODY_METHODS:
        return None
    kinds = accepted(operation, method, path)
    given = media_type(headers)
    if not kinds or not given or given in kinds:
        return None
    hint = ""
    if given == "application/x-www-form-urlencoded":
        hint = (" (curl --data-binary sends application/x-www-form-urlencoded: add "
                f"-H 'Content-Type: {kinds[-1]}'"
                + (", or send the file with -F file=@…" if "multipart/form-data" in kinds else "")
                + ")")
    return Refusal(415, ["header", "content-type"],
                   f"{method} {path} takes a body of type {', '.join(kinds)}, not {given}{hint}",
                   "unsupported_media_type")
