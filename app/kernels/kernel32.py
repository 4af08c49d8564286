"""The float32 f loop of one model class, called with the model's parameters.

The float32 twin of kernel.Kernel's f (float32.py says when a model has one and what its
error is); apart from float32.py so that the compiler process (compiler.py) can warm a
float32 module without importing the API-facing side.
"""
from __future__ import annotations

import numpy as np

from .compose import Components
from .kernel import split_work


def inputs32(*arrays) -> tuple[np.ndarray, ...]:
    """C-contiguous float32 read-only arrays (kernel.inputs in float32)."""
    out = []
    for a in arrays:
        a = np.ascontiguousarray(np.asarray(a, dtype=np.float32)).view()
        a.flags.writeable = False
        out.append(a)
    return tuple(out)


class Kernel32:
    """The float32 f loop of one :class:`Components`; parameters come from the BRDF."""

    def __init__(self, components: Components, module):
        self.components = components
        self._f_loop = module.f_loop

    @staticmethod
    def params(lobe) -> tuple[np.ndarray, ...]:
        ndf = lobe.ndf
        return inputs32(ndf.kernel_params(), lobe.masking.kernel_params(ndf),
                        lobe.g2.kernel_params(ndf), lobe.fresnel.kernel_params(),
                        lobe.diffuse.kernel_params() if lobe.diffuse is not None else ())

    def f(self, lobe, l, v) -> np.ndarray:
        """f(l, v) of a single-lobe BRDF in float32, l and v (..., 3) rounded to float32."""
        l, v = np.broadcast_arrays(np.asarray(l), np.asarray(v))
        shape = l.shape[:-1]
        l2, v2 = inputs32(l.reshape(-1), v.reshape(-1))
        out = np.empty(l2.size // 3, dtype=np.float32)
        ndf = lobe.ndf
        split_work(self._f_loop, out.size, out.size, (l2, v2, out),
                   (np.float32(ndf.alpha_x), np.float32(ndf.alpha_y), np.float32(lobe.kd),
                    *self.params(lobe)))
        return out.reshape(shape)

    def warm(self) -> None:
        """Compile (or load) the loop for the argument types :meth:`f` passes."""
        p, = inputs32(np.zeros(16))
        x = np.float32(0.5)
        self._f_loop(p, p, np.empty(1, dtype=np.float32), 0, 0, x, x, np.float32(0.0), p, p, p, p, p)
