"""Marks the plain-Python scalar formulas that an accelerator may compile.

Each model module writes, beside its vectorised numpy formulas, the same formulas for
one point as plain Python (``math`` and ``scipy.special`` only, no numpy arrays but the
float parameter array ``p``). ``@scalar`` records such a function; it changes nothing
in Python, and physics stays free of any accelerator (app/kernels compiles them).
"""
from __future__ import annotations

from typing import Callable

SCALAR_FUNCTIONS: list[Callable] = []


def scalar(fn: Callable) -> Callable:
    SCALAR_FUNCTIONS.append(fn)
    return fn
