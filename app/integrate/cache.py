"""Bounded caches of pure results that keep only whole answers.

The albedo, the E(μ, α) tables, the trade-off and the advice cache what they compute
(functools.lru_cache, bounded). Two things each of them needs, written once here:

* :class:`Keyed` — an unhashable value (a BRDF, a model spec) carried through the cache
  under a hashable key of the values it was built from (equal keys, equal values);
* :func:`complete_only` — an lru_cache that does not keep a result the request's time
  budget cut short (the budget gained a note during the call, :mod:`budget`) or that
  says itself it is incomplete: that answer is returned, with its honest larger error,
  and the next request, with a fresh budget, computes it whole. Its ``lookup`` also
  says whether the answer came from the cache (:func:`mark_cached` stamps it).
"""
from __future__ import annotations

from contextvars import ContextVar
from functools import lru_cache, wraps
from typing import Callable

import numpy as np

from . import budget


class Keyed:
    """``value`` as a cache key: equal (and hashed) by ``key`` alone."""

    __slots__ = ("value", "key")

    def __init__(self, value, key):
        self.value, self.key = value, key

    def __hash__(self):
        return hash(self.key)

    def __eq__(self, other):
        return isinstance(other, Keyed) and self.key == other.key


#: Set by :func:`complete_only`'s ``lookup``: whether the cached function ran.
_ran: ContextVar[list | None] = ContextVar("ran", default=None)


class _Cut(Exception):
    """Carries an incomplete result out of the lru_cache (which keeps no call that raises)."""


def complete_only(maxsize: int, complete: Callable[[object], bool] = lambda result: True):
    """Like ``functools.lru_cache(maxsize)``, keeping a result only if the time budget
    cut nothing during the call and ``complete(result)``. ``cache_info`` and
    ``cache_clear`` are the lru_cache's."""
    def decorate(function):
        @lru_cache(maxsize=maxsize)
        def cached(*args):
            ran = _ran.get()
            if ran is not None:
                ran[0] = True
            b = budget.current()
            notes = len(b.notes) if b else 0
            result = function(*args)
            if (b and len(b.notes) > notes) or not complete(result):
                raise _Cut(result)
            return result

        @wraps(function)
        def call(*args):
            try:
                return cached(*args)
            except _Cut as cut:
                return cut.args[0]

        def lookup(*args) -> tuple[object, bool]:
            """(the result, whether it came from the cache without computing)."""
            token = _ran.set([False])
            try:
                result = call(*args)
                return result, not _ran.get()[0]
            finally:
                _ran.reset(token)

        call.cache_info, call.cache_clear = cached.cache_info, cached.cache_clear
        call.lookup = lookup
        return call
    return decorate


def freeze(arrays):
    """Make the numpy arrays among ``arrays`` (a dict's values, or any iterable)
    read-only: a cached result is shared by every hit. Returns ``arrays``."""
    for value in (arrays.values() if isinstance(arrays, dict) else arrays):
        if isinstance(value, np.ndarray):
            value.setflags(write=False)
    return arrays


def mark_cached(data: dict, hit: bool) -> dict:
    """A cached answer says so: ``cached`` true, ``seconds`` 0 (this request computed
    nothing) and the first computation's time as ``computed_seconds``. Deterministic,
    so an HTTP revalidation of the same answer matches its ETag."""
    out = dict(data)
    out["computed_seconds"] = data.get("seconds")
    out["cached"] = bool(hit)
    if hit:
        out["seconds"] = 0.0
    return out
