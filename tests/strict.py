"""A block where numpy and Python warnings are errors: a formula that divides by zero,
overflows or makes NaN on the way to a finite answer fails the test, even when a later
``where`` hides the bad value. Underflow is allowed: a density's tail going to 0 is
the right answer, not a defect."""
from __future__ import annotations

import warnings
from contextlib import contextmanager

import numpy as np


@contextmanager
def strict():
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        with np.errstate(divide="raise", over="raise", invalid="raise", under="ignore"):
            yield
