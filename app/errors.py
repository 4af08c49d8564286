"""The errors every layer raises; ``app/api`` maps them to HTTP in one place.

- ``ParameterError``: the input is wrong whatever the load (422) — or too large (413).
- ``Busy``: the input is fine but the machine cannot answer now (503 + Retry-After):
  the time budget was spent before any work, a queue is full, a table is still building.

Nothing below ``app/api`` imports FastAPI: these are plain exceptions.
"""
from __future__ import annotations


class ParameterError(ValueError):
    """A request parameter that is well-formed but not allowed: a range, a limit, a
    combination. ``param`` names it (as the API spells it); ``message`` says what is
    allowed. ``status`` is 422 (a bad value) or 413 (more than the limits allow)."""

    def __init__(self, param: str, message: str, status: int = 422, loc: str = "query"):
        super().__init__(message)
        self.param, self.message, self.status, self.loc = param, message, status, loc


class TooLarge(ParameterError):
    """More work or data than the configured limits allow: 413, naming the limit."""

    def __init__(self, param: str, message: str, loc: str = "query"):
        super().__init__(param, message, status=413, loc=loc)


class Busy(Exception):
    """The request is valid but cannot be answered now: 503 with ``Retry-After``
    (whole seconds). ``what`` says what is busy (a table being built, the export queue)."""

    def __init__(self, message: str, retry_after: int = 2, what: str = ""):
        super().__init__(message)
        self.message, self.retry_after, self.what = message, max(1, int(retry_after)), what
