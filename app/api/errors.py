"""One error shape for every 4xx: FastAPI's own ``{"detail": [{"loc", "msg", "type"}]}``."""
from __future__ import annotations

from fastapi import Request
from fastapi.exceptions import RequestValidationError
from fastapi.responses import JSONResponse

from ..model import ModelError


class ParamError(Exception):
    """A request parameter that is well-formed but not allowed (a limit, a mismatch)."""

    def __init__(self, param: str, message: str, status_code: int = 422, loc: str = "query"):
        super().__init__(message)
        self.param, self.message, self.status_code, self.loc = param, message, status_code, loc


def _detail(loc: str, param: str, message: str, kind: str) -> dict:
    return {"detail": [{"loc": [loc, param], "msg": message, "type": kind}]}


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


async def validation_handler(request: Request, exc: RequestValidationError):
    return JSONResponse({"detail": _clean_validation(exc.errors())}, status_code=422)


async def param_error_handler(request: Request, exc: ParamError):
    return JSONResponse(_detail(exc.loc, exc.param, exc.message, "value_error"),
                        status_code=exc.status_code)


async def model_error_handler(request: Request, exc: ModelError):
    return JSONResponse(_detail("query", exc.param, exc.message, "value_error"), status_code=422)


async def internal_error_handler(request: Request, exc: Exception):
    # Never a stack trace or a file path in a response.
    return JSONResponse({"detail": "internal error"}, status_code=500)


def install(app) -> None:
    app.add_exception_handler(RequestValidationError, validation_handler)
    app.add_exception_handler(ParamError, param_error_handler)
    app.add_exception_handler(ModelError, model_error_handler)
    app.add_exception_handler(Exception, internal_error_handler)


def _allowed() -> dict[str, str]:
    from ..model import COMMON_PARAMS, choice_param_names
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
