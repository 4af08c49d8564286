"""Makes the physics' scalar formulas compilable: scipy.special and the ``@scalar``
helpers inside numba.

The scalar formulas call ``scipy.special`` functions as the numpy ones do (erfcx for
Beckmann, betainc for Student-t, the incomplete gamma and its inverses for exponential
power). numba does not know them; here each is overloaded with a call to the very
same compiled routine of ``scipy.special.cython_special``, linked by symbol name
(``llvmlite.binding.add_symbol``; a symbol, unlike a ctypes pointer, lets numba cache
the compiled loop on disk). Both paths therefore compute the same function to the bit.
Every function marked ``@scalar`` in app/physics is registered as jitable, so one
scalar formula may call another.
"""
from __future__ import annotations

import warnings

import llvmlite.binding as llvm
import numba
import scipy.special
from numba import types
from numba.core.errors import NumbaIRAssumptionWarning
from numba.extending import get_cython_function_address, overload, register_jitable

from ..physics.scalar import SCALAR_FUNCTIONS
from .compose import UNSWITCH_THRESHOLD

# name → (cython_special symbol, number of float arguments). The trailing int argument
# of each cython_special routine is its "skip dispatch" flag, passed as 0.
SPECIAL = {
    "erfcx": ("__pyx_fuse_1erfcx", 1),
    "erfc": ("__pyx_fuse_1erfc", 1),
    "betainc": ("__pyx_fuse_0betainc", 3),
    "gammainc": ("gammainc", 2),
    "gammaincc": ("gammaincc", 2),
    "gammaincinv": ("gammaincinv", 2),
    "gammainccinv": ("gammainccinv", 2),
    "gammaln": ("gammaln", 1),
}


def _external(name: str, symbol: str, arity: int):
    linked = f"brdf_scipy_{name}"
    llvm.add_symbol(linked, get_cython_function_address("scipy.special.cython_special", symbol))
    return types.ExternalFunction(linked, types.float64(*([types.float64] * arity), types.intc))


def _overload(fn, ext, arity: int) -> None:
    if arity == 1:
        overload(fn)(lambda x: (lambda x: ext(x, 0)))
    elif arity == 2:
        overload(fn)(lambda a, x: (lambda a, x: ext(a, x, 0)))
    else:
        overload(fn)(lambda a, b, x: (lambda a, b, x: ext(a, b, x, 0)))


for _name, (_symbol, _arity) in SPECIAL.items():
    _overload(getattr(scipy.special, _name), _external(_name, _symbol, _arity), _arity)

_registered: set[int] = set()


def register_scalars() -> None:
    """Make every ``@scalar`` function known so far callable from compiled code (a model
    module imported later, e.g. a test's throwaway NDF, is picked up on the next call)."""
    for fn in SCALAR_FUNCTIONS:
        if id(fn) not in _registered:
            register_jitable(inline="always")(fn)
            _registered.add(id(fn))


# LLVM's cost limit for unswitching a loop (compose.UNSWITCH_THRESHOLD says why): a
# process-wide option of LLVM, set before the first generated module compiles.
llvm.set_option("", f"--unswitch-threshold={UNSWITCH_THRESHOLD}")

# numba's own "internal pedantic check" on the SSA of inlined conditional expressions
# (``x if c else y``); the compiled result is checked against numpy by tests/kernels.
warnings.filterwarnings("ignore", category=NumbaIRAssumptionWarning)

#: Compiles a scalar formula for use inside a loop (inlined).
device = numba.njit(inline="always", nogil=True, error_model="numpy")
