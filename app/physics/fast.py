"""A fused, compiled evaluation of f(l, v) for the common models (optional: numba).

The reference evaluation in ``brdf.py`` composes small numpy functions: each term
(h, D, F, μΛ for l and v, G2) makes several temporary arrays, and masks through
``where_valid``. That is the clear version and the one every other model uses. For the
models the page shows by default it is also the bottleneck of everything heavy — the
lobe grids, large POST /eval batches and the albedo quadrature — at about 10 million
evaluations per second on one core.

Here the same formulas run as one loop per direction pair, compiled by numba: no
temporaries, each term computed once, the two cores shared by ``prange``. GGX with
Schlick's p = 5 (the default model) has its own loop without branches, which the
compiler vectorises (53 against 40 M evaluations per CPU-second through BRDF.evaluate). It covers
exactly these models, and :func:`spec_args` says so by returning None for anything else
(which then takes the reference path, unchanged):

* NDF: GGX or Beckmann (exactly those classes), any α_x, α_y;
* masking: Smith with the NDF's own Λ;
* G2: separable or height-correlated;
* Fresnel: none or Schlick (F₀, F₉₀, exponent p);
* the BRDF fields ndf, masking, g2, fresnel, kd, lambda_phi, and lobe2/lobe_mix with
  the second lobe off (brdf.py evaluates a two-lobe blend lobe by lobe); no other
  field (a new one, such as a compensation term, means a model this kernel does not
  know).

The formulas are those of ``ndf/ggx.py``, ``ndf/beckmann.py``, ``g2.py`` and
``fresnel.py``, line by line, including every limit (f = +inf where both directions
graze under height-correlated G2; 0 where h does not exist). tests/physics/
test_fast_path.py checks the kernel against the reference to 1e-12 relative over
random, grazing and degenerate directions for every model it covers.

No ``fastmath``: it would allow the compiler to assume no infinities (one of the
limits above) and to reassociate the error-free product in :func:`_beckmann_mu_lambda`.

If numba is not installed (it is an optional dependency, ``pip install '.[fast]'``),
or ``BRDF_FAST=0`` is set, :func:`spec_args` returns None and nothing here is used.
"""
from __future__ import annotations

import contextlib
import dataclasses
import math
import os
import threading

import numpy as np

# GNU OpenMP (numba's usual threading layer) lets its worker threads spin after each
# parallel loop, waiting for the next. On 2 cores that also serve other requests (or
# other processes) the spinning thread takes the CPU from the one doing the work:
# measured on the albedo at n = 17 (four parallel loops of a few ms), 48-53 ms with
# spinning against 7-16 ms with PASSIVE and 14-26 ms on one thread, under load ~5.
# Set before numba starts its thread pool (the first parallel loop); a value already in
# the environment wins.
os.environ.setdefault("OMP_WAIT_POLICY", "PASSIVE")

try:  # optional dependency
    import numba
except ImportError:  # pragma: no cover - exercised where numba is absent
    numba = None

from .fresnel import NoFresnel, Schlick
from .g2 import G2_FORMS
from .masking import MASKINGS
from .ndf.beckmann import Beckmann
from .ndf.ggx import GGX
from .vectors import HALF_VECTOR_MIN_NORM

#: numba present and not switched off with BRDF_FAST=0 (read once, at import).
AVAILABLE = numba is not None and os.environ.get("BRDF_FAST", "1") != "0"
_enabled = AVAILABLE

# Kinds passed to the kernels as small integers (a branch per element that the CPU
# predicts perfectly, rather than one compiled kernel per combination).
NDF_GGX, NDF_BECKMANN = 0, 1
G2_SEPARABLE, G2_HEIGHT_CORRELATED = 0, 1
_NDF_KINDS = {GGX: NDF_GGX, Beckmann: NDF_BECKMANN}
_G2_KINDS = {"separable": G2_SEPARABLE, "height_correlated": G2_HEIGHT_CORRELATED}
# The BRDF fields the kernel knows; lobe2/lobe_mix only when the second lobe is off.
_BRDF_FIELDS = {"ndf", "masking", "g2", "fresnel", "kd", "lambda_phi", "lobe2", "lobe_mix"}
_SCHLICK_PARAMS = {"f0", "f90", "fresnel_p"}

#: Below this many direction pairs the serial kernel is used (~0.1 ms at 5000 points).
#: On an idle machine the thread pool pays from a few hundred points on; on a busy one
#: a parallel loop waits for every thread to be scheduled (measured: 200 points taking
#: 1.3 ms instead of 7 µs while other processes used both cores), so small loops stay
#: on the calling thread.
PARALLEL_MIN = 20_000

# The Beckmann μΛ switches to its asymptotic series at a = A_SERIES, with SERIES_TERMS
# terms: the values of ndf/beckmann.py, whose comment derives them.
A_SERIES = 8.0
SERIES_TERMS = 20

SQRT_PI = math.sqrt(math.pi)
INV_PI = 1.0 / math.pi
# Veltkamp's splitting constant 2^27 + 1: x·SPLIT separates the high 26 bits of a double.
VELTKAMP_SPLIT = 134217729.0


def enabled() -> bool:
    return _enabled


@contextlib.contextmanager
def disabled():
    """Within the block every evaluation takes the reference numpy path (benchmarks
    compare the two side by side; tests use it to get the reference)."""
    global _enabled
    before, _enabled = _enabled, False
    try:
        yield
    finally:
        _enabled = before


def spec_args(brdf) -> tuple | None:
    """(ndf_kind, α_x, α_y, g2_kind, F₀, F₉₀, p, kd) if the kernel covers this BRDF, else None.

    Every check is on identity or exact type, so a new NDF subclass, masking, G2 form or
    Fresnel parameter falls back to the reference path instead of being misread.
    """
    if not _enabled:
        return None
    if {f.name for f in dataclasses.fields(brdf)} - _BRDF_FIELDS:
        return None
    if getattr(brdf, "lobe2", None) is not None and getattr(brdf, "lobe_mix", 0.0) != 0:
        return None       # a two-lobe blend: brdf.py evaluates it lobe by lobe
    ndf_kind = _NDF_KINDS.get(type(brdf.ndf))
    if ndf_kind is None or type(brdf.ndf).shape_params:
        return None
    if brdf.masking is not MASKINGS.get("smith"):
        return None
    g2_kind = next((k for name, k in _G2_KINDS.items() if brdf.g2 is G2_FORMS.get(name)), None)
    if g2_kind is None:
        return None
    fresnel = brdf.fresnel
    if type(fresnel) is NoFresnel and not NoFresnel.params:
        f0, f90, p = 1.0, 1.0, 5.0   # F₀ + (F₉₀ − F₀)(…)^p = 1 exactly
    elif type(fresnel) is Schlick and {q.name for q in Schlick.params} <= _SCHLICK_PARAMS:
        f0, f90, p = fresnel.f0, fresnel.f90, getattr(fresnel, "fresnel_p", 5.0)
    else:
        return None
    return (ndf_kind, float(brdf.ndf.alpha_x), float(brdf.ndf.alpha_y), g2_kind,
            float(f0), float(f90), float(p), float(brdf.kd))


# ---------------------------------------------------------------- scalar formulas ---
# Each mirrors one numpy function of the reference path; see the docstring there.

def _ggx_mu_lambda(mu, s):
    # ndf/ggx.py: μΛ = s² / (2(√(μ² + s²) + μ)); 0 at s = 0.
    return s * s / (2.0 * (math.sqrt(mu * mu + s * s) + mu))


def _exp_neg_square(a):
    """e^{−a²} with a² carried to twice the precision (Dekker's exact product), so that
    the cancellation in the Beckmann bracket below does not magnify its rounding."""
    hi = a * a
    c = VELTKAMP_SPLIT * a
    a_hi = c - (c - a)
    a_lo = a - a_hi
    lo = ((a_hi * a_hi - hi) + 2.0 * a_hi * a_lo) + a_lo * a_lo   # a² = hi + lo exactly
    return math.exp(-hi) * (1.0 - lo)


def _beckmann_mu_lambda(mu, s):
    # ndf/beckmann.py: μΛ = (s/2) e^{−a²} (1/√π − a·erfcx a), a = μ/s; 0 at s = 0.
    # Here e^{−a²}·erfcx(a) = erfc(a) (libm, ~1 ulp), so below A_SERIES
    #   μΛ = (s/2)(e^{−a²}/√π − a·erfc a),
    # whose two terms cancel to 1/(2a²) of their size (≤ 128× at a = 8): with both terms
    # to ~2 ulp the result keeps ~1e-13 relative. From A_SERIES on, the same asymptotic
    # series as the reference (A&S 7.1.23, SERIES_TERMS terms).
    if s <= 0.0:
        return 0.0
    a = mu / s
    if a < A_SERIES:
        return 0.5 * s * (_exp_neg_square(a) / SQRT_PI - a * math.erfc(a))
    x = 1.0 / (2.0 * a * a)
    total = 0.0
    term = x
    for k in range(1, SERIES_TERMS + 1):
        if k > 1:
            term = term * x * (2 * k - 1)
        total = total + (term if k % 2 else -term)
    return 0.5 * s * math.exp(-a * a) * total / SQRT_PI


def _mu_lambda(ndf_kind, ax, ay, wx, wy, wz):
    # ndf/base.py ShapeInvariantNDF.mu_Lambda: s = √((α_x ω_x)² + (α_y ω_y)²); 0 below.
    if wz < 0.0:
        return 0.0
    s = math.sqrt((ax * wx) ** 2 + (ay * wy) ** 2)
    if ndf_kind == NDF_GGX:
        return _ggx_mu_lambda(wz, s)
    return _beckmann_mu_lambda(wz, s)


def _D_fraction(ndf_kind, inv_ax2, inv_ay2, hx, hy, hz):
    """D = num / den without the 1/(π α_x α_y) factor (ndf/base.py D with ggx._D,
    beckmann._D), as a fraction so that one division later serves D and V together.
    Only called with h_z ≥ 0 (l and v upper)."""
    q2 = hx * hx * inv_ax2 + hy * hy * inv_ay2
    if ndf_kind == NDF_GGX:
        t = hz * hz + q2
        return 1.0, t * t
    if hz <= 0.0:          # Beckmann's limit at m_z = 0 is 0
        return 0.0, 1.0
    z2 = hz * hz
    return math.exp(-q2 / z2), z2 * z2


def _visibility_den(g2_kind, mu_l, mu_v, ml_l, ml_v):
    """4 G2-denominator: V = 1/that (g2.py), +inf where it is 0 (both graze)."""
    if g2_kind == G2_HEIGHT_CORRELATED:
        return 4.0 * (mu_l * mu_v + mu_v * ml_l + mu_l * ml_v)
    return 4.0 * ((mu_l + ml_l) * (mu_v + ml_v))


def _schlick(f0, f90, p, c):
    # fresnel.py: F₀ + (F₉₀ − F₀)(1 − c)^p, c clipped to [0, 1]; p = 5 (Schlick's) by
    # multiplication, the rest by pow.
    c = min(max(c, 0.0), 1.0)
    x = 1.0 - c
    if p == 5.0:
        x2 = x * x
        return f0 + (f90 - f0) * (x2 * x2 * x)
    return f0 + (f90 - f0) * x ** p


def _f_pair(ndf_kind, ax, ay, g2_kind, f0, f90, p, kd_over_pi,
            lx, ly, lz, vx, vy, vz):
    """f(l, v) of brdf.py BRDF.evaluate for one pair."""
    if lz < 0.0 or vz < 0.0:
        return 0.0
    sx, sy, sz = lx + vx, ly + vy, lz + vz
    norm = math.sqrt(sx * sx + sy * sy + sz * sz)
    if not norm > HALF_VECTOR_MIN_NORM:
        return kd_over_pi
    inv = 1.0 / norm
    hx, hy, hz = sx * inv, sy * inv, sz * inv
    d_num, d_den = _D_fraction(ndf_kind, 1.0 / (ax * ax), 1.0 / (ay * ay), hx, hy, hz)
    # D·F = num/den with the 1/(π α_x α_y) of D in num
    num = d_num * _schlick(f0, f90, p, vx * hx + vy * hy + vz * hz) / (math.pi * ax * ay)
    if not num > 0.0:
        return kd_over_pi
    ml_l = _mu_lambda(ndf_kind, ax, ay, lx, ly, lz)
    ml_v = _mu_lambda(ndf_kind, ax, ay, vx, vy, vz)
    v_den = _visibility_den(g2_kind, lz, vz, ml_l, ml_v)
    if not v_den > 0.0:
        return math.inf
    return num / (d_den * v_den) + kd_over_pi


def _f_pair_ggx(ax, ay, inv_ax2, inv_ay2, norm_D, g2_kind, f0, f90, kd_over_pi,
                lx, ly, lz, vx, vy, vz):
    """:func:`_f_pair` for GGX with Schlick's p = 5 (or F = 1), without branches: every
    term is computed and the special cases are selected at the end, so that the compiler
    can keep the loop in SIMD registers (measured: 55 against 39 M evaluations per CPU-
    second). Where h does not exist the terms are NaN and are not selected."""
    sx, sy, sz = lx + vx, ly + vy, lz + vz
    norm = math.sqrt(sx * sx + sy * sy + sz * sz)
    inv = 1.0 / norm
    hx, hy, hz = sx * inv, sy * inv, sz * inv
    t = hz * hz + hx * hx * inv_ax2 + hy * hy * inv_ay2           # GGX: D = norm_D / t²
    c = min(max(vx * hx + vy * hy + vz * hz, 0.0), 1.0)
    x = 1.0 - c
    x2 = x * x
    num = (f0 + (f90 - f0) * (x2 * x2 * x)) * norm_D
    sl2 = (ax * lx) ** 2 + (ay * ly) ** 2
    sv2 = (ax * vx) ** 2 + (ay * vy) ** 2
    ml_l = sl2 / (2.0 * (math.sqrt(lz * lz + sl2) + lz))
    ml_v = sv2 / (2.0 * (math.sqrt(vz * vz + sv2) + vz))
    hc = 4.0 * (lz * vz + vz * ml_l + lz * ml_v)
    sep = 4.0 * ((lz + ml_l) * (vz + ml_v))
    v_den = hc if g2_kind == G2_HEIGHT_CORRELATED else sep
    spec = num / (t * t * v_den) if v_den > 0.0 else math.inf
    spec = spec if num > 0.0 else 0.0
    spec = spec if norm > HALF_VECTOR_MIN_NORM else 0.0
    return spec + kd_over_pi if (lz >= 0.0) & (vz >= 0.0) else 0.0


# Each loop comes twice, parallel (prange) and serial (range): numba's on-disk cache
# keys a function by its source, not by its `parallel` flag, so one Python function
# cannot be cached in both forms.
def _f_loop_parallel(l, v, out, ndf_kind, ax, ay, g2_kind, f0, f90, p, kd_over_pi):
    for i in _prange(out.shape[0]):
        out[i] = _f_pair(ndf_kind, ax, ay, g2_kind, f0, f90, p, kd_over_pi,
                         l[i, 0], l[i, 1], l[i, 2], v[i, 0], v[i, 1], v[i, 2])


def _f_loop_serial(l, v, out, ndf_kind, ax, ay, g2_kind, f0, f90, p, kd_over_pi):
    for i in range(out.shape[0]):
        out[i] = _f_pair(ndf_kind, ax, ay, g2_kind, f0, f90, p, kd_over_pi,
                         l[i, 0], l[i, 1], l[i, 2], v[i, 0], v[i, 1], v[i, 2])


def _f_ggx_loop_parallel(l, v, out, ax, ay, g2_kind, f0, f90, kd_over_pi):
    inv_ax2, inv_ay2, norm_D = 1.0 / (ax * ax), 1.0 / (ay * ay), 1.0 / (math.pi * ax * ay)
    for i in _prange(out.shape[0]):
        out[i] = _f_pair_ggx(ax, ay, inv_ax2, inv_ay2, norm_D, g2_kind, f0, f90, kd_over_pi,
                             l[i, 0], l[i, 1], l[i, 2], v[i, 0], v[i, 1], v[i, 2])


def _f_ggx_loop_serial(l, v, out, ax, ay, g2_kind, f0, f90, kd_over_pi):
    inv_ax2, inv_ay2, norm_D = 1.0 / (ax * ax), 1.0 / (ay * ay), 1.0 / (math.pi * ax * ay)
    for i in range(out.shape[0]):
        out[i] = _f_pair_ggx(ax, ay, inv_ax2, inv_ay2, norm_D, g2_kind, f0, f90, kd_over_pi,
                             l[i, 0], l[i, 1], l[i, 2], v[i, 0], v[i, 1], v[i, 2])


_prange = range
JIT_OPTIONS = dict(nogil=True, error_model="numpy")
if numba is not None:
    _prange = numba.prange
    _device = numba.njit(inline="always", **JIT_OPTIONS)
    _ggx_mu_lambda = _device(_ggx_mu_lambda)
    _exp_neg_square = _device(_exp_neg_square)
    _beckmann_mu_lambda = _device(_beckmann_mu_lambda)
    _mu_lambda = _device(_mu_lambda)
    _D_fraction = _device(_D_fraction)
    _visibility_den = _device(_visibility_den)
    _schlick = _device(_schlick)
    _f_pair = _device(_f_pair)
    _f_pair_ggx = _device(_f_pair_ggx)


# The per-term formulas, for other compiled loops (the albedo quadrature's integrand in
# app/integrate/albedo_kernel.py): numba-compiled device functions when numba is there.
mu_lambda = _mu_lambda
visibility_den = _visibility_den
schlick = _schlick


def _compile(func, parallel: bool):
    """numba.njit with an on-disk cache where a cache directory is writable (a read-only
    install compiles once per process instead)."""
    try:
        return numba.njit(parallel=parallel, cache=True, **JIT_OPTIONS)(func)
    except RuntimeError:   # "cannot cache function ...: no locator available"
        return numba.njit(parallel=parallel, **JIT_OPTIONS)(func)


_kernels: dict = {}
_kernels_lock = threading.Lock()
# numba's fallback threading layer (workqueue) must not be entered by two threads at
# once; the API serves requests from a thread pool. One parallel kernel at a time: a
# caller that finds it busy runs the serial kernel instead (2 cores are busy anyway).
_parallel_lock = threading.Lock()


def kernel(func, parallel: bool):
    """The compiled ``func`` (compiled on first use, then cached on disk)."""
    if numba is None:
        return func   # plain Python: only tests call it so (on a few points)
    key = f"{func.__module__}.{func.__qualname__}"
    k = _kernels.get(key)
    if k is None:
        with _kernels_lock:
            k = _kernels.get(key)
            if k is None:
                k = _kernels[key] = _compile(func, parallel)
    return k


def inputs(*arrays, shape: tuple | None = None) -> tuple[np.ndarray, ...]:
    """The loops' input arrays as C-contiguous float64 views that are read-only.

    numba compiles one version of a loop per argument type, and an array's type includes
    whether it is writable: callers pass both kinds (cached node arrays are frozen, fresh
    ones are not), and each new mix compiled the loop again, ~1 s, in whichever request
    met it first (app/warmup.py). Read-only views of every input (no copy where the
    data already is contiguous float64) leave one type per loop. ``shape``: broadcast
    each array to it first."""
    out = []
    for a in arrays:
        a = np.asarray(a, dtype=float)
        if shape is not None:
            a = np.broadcast_to(a, shape)
        a = np.ascontiguousarray(a).view()
        a.flags.writeable = False
        out.append(a)
    return tuple(out)


def run(loops: tuple, n_items: int, *args) -> None:
    """Run ``loops = (parallel_loop, serial_loop)`` on ``args``: the parallel one when
    ``n_items`` makes it pay and the thread pool is free, else the serial one."""
    parallel_loop, serial_loop = loops
    if n_items >= PARALLEL_MIN and _parallel_lock.acquire(blocking=False):
        try:
            kernel(parallel_loop, True)(*args)
        finally:
            _parallel_lock.release()
    else:
        kernel(serial_loop, False)(*args)


F_LOOPS = (_f_loop_parallel, _f_loop_serial)
F_GGX_LOOPS = (_f_ggx_loop_parallel, _f_ggx_loop_serial)


def compile_loops() -> None:
    """Compile (or load from numba's disk cache) both forms of both f loops, on one
    direction pair with the argument types :func:`spec_args` gives (Python int kinds,
    float parameters), so later calls find that signature compiled (the values are any
    valid ones: only their types select the compiled version). app/warmup.py calls it
    before any request is timed."""
    if numba is None:
        return
    (l,) = inputs([[0.0, 0.0, 1.0]])
    out = np.empty(1)
    for parallel, loop in zip((True, False), F_GGX_LOOPS):
        kernel(loop, parallel)(l, l, out, 0.5, 0.5, G2_HEIGHT_CORRELATED, 0.04, 1.0, 0.0)
    for parallel, loop in zip((True, False), F_LOOPS):
        kernel(loop, parallel)(l, l, out, NDF_BECKMANN, 0.5, 0.5, G2_HEIGHT_CORRELATED,
                               0.04, 1.0, 5.0, 0.0)


def evaluate_f(args: tuple, l: np.ndarray, v: np.ndarray) -> np.ndarray:
    """f(l, v) for l, v broadcastable (..., 3), with ``args`` from :func:`spec_args`."""
    l, v = np.broadcast_arrays(np.asarray(l, dtype=float), np.asarray(v, dtype=float))
    shape = l.shape[:-1]
    l2, v2 = inputs(l.reshape(-1, 3), v.reshape(-1, 3))
    out = np.empty(l2.shape[0])
    ndf_kind, ax, ay, g2_kind, f0, f90, p, kd = args
    if ndf_kind == NDF_GGX and p == 5.0:
        run(F_GGX_LOOPS, out.shape[0], l2, v2, out, ax, ay, g2_kind, f0, f90, kd / math.pi)
    else:
        run(F_LOOPS, out.shape[0], l2, v2, out, ndf_kind, ax, ay, g2_kind, f0, f90, p,
            kd / math.pi)
    return out.reshape(shape)
