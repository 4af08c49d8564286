"""The albedo quadrature's integrand as one compiled loop (optional: numba).

``albedo._integrate_order`` lays the nodes — ψ (cos, sin, weight), the disk exit U(ψ)
and 1 − U, and the rules in u (albedo._u_rule, albedo._log_rule) — in numpy, at O(n·N)
cost. Everything at
the O(n·N²) nodes is the integrand

    g = 4 F(v·m) V(l, v) μ_l (v·m)/μ_m,   l the mirror of v about m(ρ̃(u), ψ),

which in numpy makes some thirty temporary arrays of n × 2N × N. Here it is one loop
over (μ, ψ) rows, the u-sum inside, using the same per-term formulas as the BRDF kernel
(app/physics/fast.py). It covers the models that kernel covers, for NDFs whose inverse
radial CDF it knows (GGX: u/(1 − u); Beckmann: −log(1 − u)); :func:`spec_args` returns
None for the rest, which keep the numpy integrand.

tests/physics/test_albedo_kernel.py compares it with the numpy integrand node set by
node set.
"""
from __future__ import annotations

import math

import numpy as np

from ..physics import fast

def spec_args(brdf) -> tuple | None:
    """(ndf_kind, α_x, α_y, g2_kind, F₀, F₉₀, p) when the compiled integrand covers
    ``brdf`` (kd is not part of the specular integral), else None."""
    args = fast.spec_args(brdf)
    if args is None or brdf.g2.needs_phi:
        return None
    return args[:7]


def _radial_r2(ndf_kind, u, one_minus_u):
    """r̃² with C(r̃) = u, from u while u < ½ and from 1 − u (kept exact by the caller)
    beyond, as albedo._integrate_order does with radial_cdf_inv / radial_ccdf_inv.
    GGX: C = r̃²/(1 + r̃²); Beckmann: C = 1 − exp(−r̃²)."""
    if ndf_kind == fast.NDF_GGX:
        if u < 0.5:
            return u / (1.0 - u)
        return (1.0 - one_minus_u) / one_minus_u
    if u < 0.5:
        return -math.log1p(-u)
    return -math.log(one_minus_u)


def _row(ndf_kind, ax, ay, g2_kind, f0, f90, p, vx, vy, vz, ml_v, c, s, U, V0,
         head, tail, w_u, h, dh, use_log):
    """Σ_j g(u_j) du_j along one ψ (cos c, sin s) for view v. The u-rule: u = U head_j,
    1 − u = V0 + U tail_j, du = U w_u_j; the log rule (use_log and V0 > 0):
    1 − u = V0^h_j, du = −ln V0 (1 − u) dh_j (albedo._u_rule, albedo._log_rule)."""
    total = 0.0
    log_rule = use_log and V0 > 0.0
    L = math.log(V0) if log_rule else 0.0
    for j in range(tail.shape[0]):
        if log_rule:
            one_minus_u = math.exp(h[j] * L)
            u = -math.expm1(h[j] * L)
            du = -L * one_minus_u * dh[j]
        else:
            u = U * head[j]
            one_minus_u = V0 + U * tail[j]
            du = U * w_u[j]
        rho = math.sqrt(_radial_r2(ndf_kind, u, one_minus_u))
        X = ax * rho * c
        Y = ay * rho * s
        k = vz - vx * X - vy * Y                    # (v·m)/μ_m
        inv_len2 = 1.0 / (1.0 + X * X + Y * Y)      # μ_m²
        two_vm_mum = 2.0 * k * inv_len2
        mu_l = two_vm_mum - vz
        if not mu_l > 0.0:
            continue
        lx = -two_vm_mum * X - vx
        ly = -two_vm_mum * Y - vy
        ml_l = fast.mu_lambda(ndf_kind, ax, ay, lx, ly, mu_l)
        den4 = fast.visibility_den(g2_kind, mu_l, vz, ml_l, ml_v)
        F = fast.schlick(f0, f90, p, k * math.sqrt(inv_len2))
        g = 4.0 * F * mu_l * k / den4 if den4 > 0.0 else math.inf
        total += g * du
    return total


def _rows_parallel(v, cp, sp, U, V0, head, tail, w_u, h, dh, use_log, out, ndf_kind, ax, ay, g2_kind, f0, f90, p):
    n_psi = cp.shape[1]
    for q in _prange(cp.shape[0] * n_psi):
        i = q // n_psi
        j = q - i * n_psi
        vx, vy, vz = v[i, 0], v[i, 1], v[i, 2]
        ml_v = fast.mu_lambda(ndf_kind, ax, ay, vx, vy, vz)
        out[i, j] = _row(ndf_kind, ax, ay, g2_kind, f0, f90, p, vx, vy, vz, ml_v,
                         cp[i, j], sp[i, j], U[i, j], V0[i, j], head, tail, w_u, h, dh, use_log)


def _rows_serial(v, cp, sp, U, V0, head, tail, w_u, h, dh, use_log, out, ndf_kind, ax, ay, g2_kind, f0, f90, p):
    # the same as _rows_parallel with range (see fast.py on why there are two)
    n_psi = cp.shape[1]
    for q in range(cp.shape[0] * n_psi):
        i = q // n_psi
        j = q - i * n_psi
        vx, vy, vz = v[i, 0], v[i, 1], v[i, 2]
        ml_v = fast.mu_lambda(ndf_kind, ax, ay, vx, vy, vz)
        out[i, j] = _row(ndf_kind, ax, ay, g2_kind, f0, f90, p, vx, vy, vz, ml_v,
                         cp[i, j], sp[i, j], U[i, j], V0[i, j], head, tail, w_u, h, dh, use_log)


_prange = range
if fast.numba is not None:
    _prange = fast.numba.prange
    _radial_r2 = fast.numba.njit(inline="always", **fast.JIT_OPTIONS)(_radial_r2)
    _row = fast.numba.njit(inline="always", **fast.JIT_OPTIONS)(_row)

ROW_LOOPS = (_rows_parallel, _rows_serial)


def compile_loops() -> None:
    """Compile (or load from numba's disk cache) both forms of the row loop, on one
    node with the argument types :func:`integrate` passes (see fast.compile_loops)."""
    if fast.numba is None:
        return
    v, node, rule = fast.inputs([[0.0, 0.0, 1.0]], [[0.5]], [0.5])
    for parallel, loop in zip((True, False), ROW_LOOPS):
        fast.kernel(loop, parallel)(v, node, node, node, node, rule, rule, rule, rule, rule,
                                    False, np.empty((1, 1)), fast.NDF_GGX, 0.5, 0.5,
                                    fast.G2_HEIGHT_CORRELATED, 0.04, 1.0, 5.0)


def integrate(args: tuple, v, cp, sp, U, V0, head, tail, w_u, h, dh, use_log: bool,
              w_psi) -> np.ndarray:
    """(1/2π) Σ_ψ w_ψ Σ_u g du for each view direction: E_spec at v (n, 3).

    ``cp``, ``sp``, ``U``, ``V0``: (n, P) cos ψ, sin ψ, the disk exit U = C(R(ψ)) and
    1 − U; ``head``, ``tail``, ``w_u``: (N,) the u-rule, u = U head, 1 − u = V0 + U tail,
    du = U w_u; ``h``, ``dh``: (N,) the log rule, used where ``use_log`` and V0 > 0;
    ``w_psi``: (P,) ψ weights.
    """
    (v,) = fast.inputs(v)
    cp, sp, U, V0 = fast.inputs(cp, sp, U, V0, shape=np.shape(cp))
    head, tail, w_u, h, dh = fast.inputs(*(np.ravel(a) for a in (head, tail, w_u, h, dh)))
    rows = np.empty(cp.shape)
    fast.run(ROW_LOOPS, rows.size * tail.size, v, cp, sp, U, V0, head, tail, w_u, h, dh,
             bool(use_log), rows, *args)
    return rows @ np.asarray(w_psi, dtype=float) / (2.0 * np.pi)
