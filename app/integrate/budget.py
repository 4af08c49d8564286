"""A time budget for the adaptive computations of one request.

The HTTP layer opens a budget per request (``with budget.limit(seconds): ...``,
setting ``BRDF_MAX_SECONDS``); an adaptive loop asks :func:`current` before each
refinement whether the next level still fits, and stops — returning its coarser value
with its honest, larger error — when it would not. Work that is not adaptive is bounded
by size limits instead (``app/config.py``).

A context variable rather than an argument: it reaches the loop through the threads a
server runs its handlers in (contexts are copied into them), without a ``budget``
argument in every signature between the route and the quadrature. Outside a request
there is no budget and nothing is cut.
"""
from __future__ import annotations

import time
from contextlib import contextmanager
from contextvars import ContextVar
from dataclasses import dataclass, field

_CURRENT: ContextVar["Budget | None"] = ContextVar("brdf_budget", default=None)


@dataclass
class Budget:
    seconds: float
    start: float = field(default_factory=time.perf_counter)
    #: one line per computation that stopped early, saying where and why
    notes: list[str] = field(default_factory=list)

    def elapsed(self) -> float:
        return time.perf_counter() - self.start

    def affords(self, predicted_seconds: float) -> bool:
        """Whether work predicted to take this long still ends within the budget."""
        return self.elapsed() + predicted_seconds <= self.seconds

    def cut(self, note: str) -> None:
        self.notes.append(note)


def current() -> Budget | None:
    return _CURRENT.get()


@contextmanager
def limit(seconds: float):
    """Run the enclosed work under a fresh budget of ``seconds``."""
    b = Budget(float(seconds))
    token = _CURRENT.set(b)
    try:
        yield b
    finally:
        _CURRENT.reset(token)
