"""A model's compiled loops, called with the model's parameters as float arrays.

The loops release the GIL (``nogil``); above PARALLEL_MIN items the work is split into
one contiguous block per core and the blocks run on a small thread pool, so no numba
threading layer (and none of its environment) is involved.
"""
from __future__ import annotations

import os
from concurrent.futures import ThreadPoolExecutor

import numpy as np

from ..physics import smith_integral as si
from .compose import Components

#: Below this many items (pairs, or quadrature nodes) one thread does the work: a block
#: handed to a pool thread costs ~50 µs, ~1 000 pair evaluations.
PARALLEL_MIN = 20_000
#: The loops each use of a model needs, compiled together (a part is ready when all of
#: its loops are): evaluating f (direction pairs, or angles in degrees) and integrating
#: the albedo (the quadrature's rows). Both carry ``smith_h``, the Smith table's integrals
#: of the model's NDF (~0.2 s; compiled once, whichever part comes first). A table build
#: needs only "albedo", ~1–2 s of compiling instead of the ~5 s of all four loops.
PARTS = {"f": ("f_loop", "f_deg_loop", "smith_h"), "albedo": ("albedo_rows", "smith_h")}
WORKERS = max(1, min(os.cpu_count() or 1, 8))
_pool = ThreadPoolExecutor(max_workers=WORKERS, thread_name_prefix="kernel")


def inputs(*arrays, shape: tuple | None = None) -> tuple[np.ndarray, ...]:
    """C-contiguous float64 read-only views (copies only where needed). numba compiles
    one version per array type, and writability is part of it: with every input
    read-only, each loop has exactly the one version the warm-up compiled."""
    out = []
    for a in arrays:
        a = np.asarray(a, dtype=float)
        if shape is not None:
            a = np.broadcast_to(a, shape)
        a = np.ascontiguousarray(a).view()
        a.flags.writeable = False
        out.append(a)
    return tuple(out)


def split_work(loop, n: int, work: int, before: tuple, after: tuple) -> None:
    """loop(*before, start, stop, *after) over [0, n), in one block per core on the pool
    when the ``work`` (evaluations) makes it pay."""
    k = min(WORKERS, n)
    if work < PARALLEL_MIN or k < 2:
        loop(*before, 0, n, *after)
        return
    edges = np.linspace(0, n, k + 1).astype(np.int64)
    blocks = [(int(a), int(b)) for a, b in zip(edges[:-1], edges[1:]) if b > a]
    futures = []
    for i, (a, b) in enumerate(blocks):
        try:
            futures.append(_pool.submit(loop, *before, a, b, *after))
        except RuntimeError:
            # the interpreter is exiting (concurrent.futures' atexit hook has shut the pool)
            # while a daemon thread (the table builder) still computes: finish here
            for a_, b_ in blocks[i:]:
                loop(*before, a_, b_, *after)
            break
    for f in futures:
        f.result()


class Kernel:
    """The loops of one :class:`Components`; parameters come from the BRDF at each call."""

    def __init__(self, components: Components, module):
        self.components = components
        self._f_loop = module.f_loop
        self._f_deg_loop = module.f_deg_loop
        self._albedo_rows = module.albedo_rows
        self._smith_h = module.smith_h

    @staticmethod
    def params(lobe) -> tuple[np.ndarray, ...]:
        """(p_ndf, p_mask, p_g2, p_fresnel) of a single-lobe BRDF."""
        ndf = lobe.ndf
        return inputs(ndf.kernel_params(), lobe.masking.kernel_params(ndf),
                      lobe.g2.kernel_params(ndf), lobe.fresnel.kernel_params())

    @staticmethod
    def diffuse_params(lobe) -> np.ndarray:
        """p_diffuse of a BRDF: its diffuse model's kernel_params() (none for Lambert)."""
        return inputs(lobe.diffuse.kernel_params() if lobe.diffuse is not None else ())[0]

    def f(self, lobe, l, v) -> np.ndarray:
        """f(l, v) of a single-lobe BRDF (no second lobe, no compensation) for l, v
        broadcastable (..., 3)."""
        l, v = np.broadcast_arrays(np.asarray(l, dtype=float), np.asarray(v, dtype=float))
        shape = l.shape[:-1]
        l2, v2 = inputs(l.reshape(-1), v.reshape(-1))     # flat: x0 y0 z0 x1 ... (f_loop)
        out = np.empty(l2.size // 3)
        ndf = lobe.ndf
        split_work(self._f_loop, out.size, out.size, (l2, v2, out),
               (float(ndf.alpha_x), float(ndf.alpha_y), float(lobe.kd), *self.params(lobe),
                self.diffuse_params(lobe)))
        return out.reshape(shape)

    def f_deg(self, lobe, theta_l, phi_l, theta_v, phi_v, out=None) -> np.ndarray:
        """f of a single-lobe BRDF at angles in degrees (l at θ_l, φ_l; v at θ_v, φ_v),
        broadcast together: the directions are built inside the loop, as
        physics/vectors.direction_deg builds them. ``out``: a contiguous float64 array of
        the broadcast size to write into (no array allocated, none copied)."""
        shape = np.broadcast_shapes(*(np.shape(a) for a in (theta_l, phi_l, theta_v, phi_v)))
        angles = inputs(*(np.broadcast_to(np.asarray(a, dtype=float), shape).reshape(-1)
                          for a in (theta_l, phi_l, theta_v, phi_v)))
        flat = np.empty(angles[0].size) if out is None else out.reshape(-1)
        ndf = lobe.ndf
        split_work(self._f_deg_loop, flat.size, flat.size, (*angles, flat),
               (float(ndf.alpha_x), float(ndf.alpha_y), float(lobe.kd), *self.params(lobe),
                self.diffuse_params(lobe)))
        return flat.reshape(shape) if out is None else out

    def albedo_rows(self, lobe, v, cp, sp, U, V0, head, tail, w_u, h, dh, use_log) -> np.ndarray:
        """Σ_u g du along each ψ of each view (n, P): the albedo integrand at the nodes of
        albedo._integrate_order (see there for the rules' arguments)."""
        (v,) = inputs(v)
        cp, sp, U, V0 = inputs(cp, sp, U, V0, shape=np.shape(cp))
        head, tail, w_u, h, dh = inputs(*(np.ravel(a) for a in (head, tail, w_u, h, dh)))
        rows = np.empty(cp.shape)
        ndf = lobe.ndf
        split_work(self._albedo_rows, rows.size, rows.size * tail.size,
               (v, cp, sp, U, V0, head, tail, w_u, h, dh, bool(use_log), rows),
               (float(ndf.alpha_x), float(ndf.alpha_y), *self.params(lobe)))
        return rows

    def smith_h(self, ndf, a) -> tuple[np.ndarray, np.ndarray, np.ndarray]:
        """h(a), dh/da and d²h/da² at a ≥ 0 of the Smith table
        (physics/smith_integral.h_derivatives: the same rule, nodes and substitution)."""
        one_minus_t, dt = si.t_rule()
        k = si.tail_power(ndf)
        a, power, weight, p = inputs(a, one_minus_t ** k, k * one_minus_t ** (k - 1.0) * dt,
                                     ndf.radial_params())
        h, slope, curvature = np.empty(a.size), np.empty(a.size), np.empty(a.size)
        split_work(self._smith_h, a.size, a.size * weight.size,
               (a, power, weight, p, h, slope, curvature), ())
        return h, slope, curvature

    def warm(self, part: str | None = None) -> None:
        """Compile (or load from numba's cache) the loops of ``part`` (every loop when
        None), on one point each (none for smith_h), with the argument types the calls
        above use."""
        for name in loops_of(part):
            getattr(self, f"_warm_{name}")()

    def _warm_f_loop(self):
        p = _any_params()
        self._f_loop(p, p, np.empty(1), 0, 0, 0.5, 0.5, 0.0, p, p, p, p, p)

    def _warm_f_deg_loop(self):
        p = _any_params()
        self._f_deg_loop(p, p, p, p, np.empty(1), 0, 0, 0.5, 0.5, 0.0, p, p, p, p, p)

    def _warm_albedo_rows(self):
        p = _any_params()
        l, = inputs([[0.0, 0.0, 1.0]])
        node, = inputs([[0.5]])
        rule, = inputs([0.5])
        self._albedo_rows(l, node, node, node, node, rule, rule, rule, rule, rule, False,
                          np.empty((1, 1)), 0, 0, 0.5, 0.5, p, p, p, p)

    def _warm_smith_h(self):
        rule, = inputs([0.5])
        self._smith_h(rule, rule, rule, _any_params(), np.empty(1), np.empty(1), np.empty(1), 0, 0)


def loops_of(part: str | None) -> tuple[str, ...]:
    """The loop names of ``part`` (one of PARTS), or of every part for None."""
    if part is None:
        return tuple(dict.fromkeys(name for names in PARTS.values() for name in names))
    return PARTS[part]


def _any_params() -> np.ndarray:
    """Parameters for a warm-up call: long enough for any formula's (the loops read them
    into tuples before their first iteration; none iterates here)."""
    return inputs(np.zeros(16))[0]
