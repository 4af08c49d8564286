"""The one place where errors become HTTP responses.

Every layer raises :mod:`app.errors`: ``ParameterError`` → its status (422, or 413 for
``TooLarge``), ``Busy`` → 503 with ``Retry-After``. FastAPI's validation errors → 422.
The body is always FastAPI's own shape ``{"detail": [{"loc", "msg", "type"}]}``. A
handler that fails itself answers a minimal body with the same status, never a 500.
"""
from __future__ import annotations

import json
import logging

from fastapi import Request, Response
from fastapi.exceptions import RequestValidationError

from ..errors import Busy, ParameterError
from ..model import COMMON_PARAMS, choice_param_names

log = logging.getLogger("app")


def _detail(loc: list, message: str, kind: str) -> dict:
    return {"detail": [{"loc": loc, "msg": message, "type": kind}]}


def _respond(status: int, payload: dict, headers: dict | None = None) -> Response:
    """JSON out without the encoder that could fail on an odd message: ``default=str``
    turns anything unexpected into text."""
    body = json.dumps(payload, ensure_ascii=False, default=str, allow_nan=False)
    return Response(body, status_code=status, media_type="application/json", headers=headers)


def _safe(status_of):
    """Wrap a handler so that an exception inside it still answers with the status the
    error asked for (``status_of(exc)``) and a generic message, never a 500."""
    def wrap(handler):
        async def safe(request: Request, exc: Exception):
            try:
                return handler(exc)
            except Exception:
                log.exception("error handler failed for %s", type(exc).__name__)
                return Response(b'{"detail":"error"}', status_code=status_of(exc),
                                media_type="application/json")
        safe.__wrapped__ = handler
        return safe
    return wrap


def _clean_validation(errors) -> list[dict]:
    """FastAPI's validation errors without the echoed input or internal context
    (which may contain exception objects that are not JSON)."""
    out = []
    for e in errors:
        loc = list(e.get("loc", ()))
        msg = e.get("msg", "")
        name = next((x for x in loc[1:] if isinstance(x, str)), None)
        if e.get("type") == "extra_forbidden":
            msg = f"{name}: unknown parameter for this endpoint"
        elif name in ALLOWED and e.get("type") != "literal_error":
            msg = f"{name}: {msg}; allowed: {ALLOWED[name]}"
        elif name:
            msg = f"{name}: {msg}"
        out.append({"loc": loc, "msg": msg, "type": e.get("type", "")})
    return out


@_safe(lambda exc: 422)
def validation_handler(exc: RequestValidationError) -> Response:
    return _respond(422, {"detail": _clean_validation(exc.errors())})


@_safe(lambda exc: exc.status)
def parameter_handler(exc: ParameterError) -> Response:
    return _respond(exc.status, _detail([exc.loc, exc.param], exc.message, "value_error"))


@_safe(lambda exc: 503)
def busy_handler(exc: Busy) -> Response:
    loc = ["query", exc.what or "server"]
    return _respond(503, _detail(loc, exc.message, "busy"),
                    headers={"Retry-After": str(exc.retry_after), "Cache-Control": "no-store"})


@_safe(lambda exc: 503)
def memory_handler(exc: MemoryError) -> Response:
    """Out of memory is the machine's state, not the input's fault (the cost model refuses
    what could never fit): busy, retry."""
    log.warning("out of memory answering a request: %r", exc)
    return busy_handler.__wrapped__(Busy("the server has not enough free memory for this "
                                         "request now: retry", retry_after=5, what="memory"))


async def internal_error_handler(request: Request, exc: Exception) -> Response:
    # Never a stack trace or a file path in a response: the trace goes to the log.
    log.exception("unhandled error in %s %s", request.method, request.url.path)
    return Response(b'{"detail":"internal error"}', status_code=500, media_type="application/json")


def install(app) -> None:
    app.add_exception_handler(RequestValidationError, validation_handler)
    app.add_exception_handler(ParameterError, parameter_handler)
    app.add_exception_handler(Busy, busy_handler)
    app.add_exception_handler(MemoryError, memory_handler)
    app.add_exception_handler(Exception, internal_error_handler)


def _allowed() -> dict[str, str]:
    out = {p.name: p.range_text() for p in COMMON_PARAMS}
    for name, owners in choice_param_names().items():
        out[name] = "; ".join(f"{p.range_text()} with {who}" for who, p in owners.items())
    out.update({"theta_i_deg": "[0, 90] degrees", "theta_o_deg": "[0, 90] degrees",
                "phi_i_deg": "[-360, 360] degrees", "phi_o_deg": "[-360, 360] degrees",
                "phi_deg": "[-360, 360] degrees", "mu": "[0, 1]"})
    # not "tol": its range differs between endpoints (albedo [1e-7, 1e-2], advise
    # [1e-4, 0.5]); pydantic's own message names the bound that was crossed
    return out


ALLOWED = _allowed()
