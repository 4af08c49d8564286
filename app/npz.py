"""Reading ``.npz`` files from several threads at once, safely on every CPython.

numpy parses each array's header with ``ast.literal_eval``. Before CPython 3.11.8 and
3.12.2 the AST constructor kept its recursion counter in state shared by all threads
(cpython issue #106905, fixed by pull request #113035): when a garbage collection inside
one thread's parse ran a finalizer that let another thread parse too, one of them failed
with ``SystemError: AST constructor recursion depth mismatch``. The server reads data sets
and E(μ, α) tables in its request threads and table builders, so under concurrent GETs a
data set answered 500 (1 of 100 GETs on two workers, 3.11.7). Every read here holds one
process-wide lock; a read is a few milliseconds.
"""
from __future__ import annotations

import threading
from os import PathLike

import numpy as np

#: held while a thread reads an .npz file (and so parses its arrays' headers)
_READING = threading.Lock()


def read(path: str | PathLike) -> dict[str, np.ndarray]:
    """Every array of the ``.npz`` file at ``path``, read whole (no pickles). Raises what
    ``np.load`` raises for a missing or damaged file (OSError, ValueError, KeyError...)."""
    with _READING, np.load(path, allow_pickle=False) as arrays:
        return {name: arrays[name] for name in arrays.files}
