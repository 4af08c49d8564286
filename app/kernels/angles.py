"""Directions from angles in degrees, inside the compiled loops (compose.py's f_deg_loop).

The API takes angles in degrees; building ω = (sinθ cosφ, sinθ sinφ, cosθ) in numpy
before the loop cost more than f itself. Here sin and cos of degrees are arithmetic only
(an exact reduction by 90°, then two polynomials), so the loops below vectorise, and they
are exact 0 and ±1 at multiples of 90° as physics/vectors.direction_deg promises.

One module for every model: the generated modules import these functions, so they are
written once (one spelling) and compiled once per process; numba links them into each
model's f_deg_loop (and optimises them there again), so a model's first compile did not
grow with the isotropic loop: two models 10.3-10.9 s against 9.8-11.1 s with one loop
written into each model's module (fresh kernel directories, /tmp script). Not cached by numba (its cache would be written beside this file,
inside the package): a model's cached loop holds its own copy of them, and the models'
file names hash this module's source (compose._fingerprint), so an edit here recompiles.
"""
from __future__ import annotations

import math

import numba

from .special import device

#: pairs whose directions are built at once by f_deg_loop (6 × 8 bytes each: in L1)
BLOCK = 256
DEG = math.pi / 180.0
#: 1.5·2^52: (x + ROUND) − ROUND is x rounded to an integer (|x| < 2^51), no call
ROUND = 6755399441055744.0
#: sin x = x + x³ S(x²), cos x = 1 + x² C(x²) on |x| ≤ π/4: least-squares fits in y = x² at 60
#: Chebyshev nodes, solved in 40-digit arithmetic (mpmath) and rounded to doubles; the
#: largest error measured against mpmath over 20 001 x is 1.2e-16 (sin, relative) and
#: 1.2e-16 (cos): the same as the Taylor series to x¹⁷ and x¹⁶, with three terms fewer.
S = (-0.16666666666666666, 0.00833333333333095, -0.0001984126983675979, 2.7557316103105014e-06,
     -2.5051131947374594e-08, 1.5918135932869774e-10)
C = (-0.5, 0.04166666666666664, -0.0013888888888880777, 2.4801587293694974e-05,
     -2.7557315566815476e-07, 2.0875886806287426e-09, -1.1368002341468553e-11)
S0, S1, S2, S3, S4, S5 = S
C0, C1, C2, C3, C4, C5, C6 = C


@device
def sincos_deg(a, e):
    # (sin, cos) of a + e degrees, e a correction far below a's last bit (the rounding error
    # of a difference in directions_deg_isotropic; -0.0 for one angle: x + -0.0 is x for
    # every x, -0.0 included, so the compiler drops the add); exact 0 and ±1 at
    # multiples of 90° (as physics/vectors.direction_deg): the reduction to x in [-45°, 45°]
    # is exact in degrees (a - 360 k and r - 90 q are representable), then e is added and
    # the polynomials S and C in radians (about 1 ulp; see their definition).
    r = a - 360.0 * ((a * (1.0 / 360.0) + ROUND) - ROUND)
    q = (r * (1.0 / 90.0) + ROUND) - ROUND
    x = ((r - 90.0 * q) + e) * DEG
    x2 = x * x
    s = x + x * x2 * (S0 + x2 * (S1 + x2 * (S2 + x2 * (S3 + x2 * (S4 + x2 * S5)))))
    c = 1.0 + x2 * (C0 + x2 * (C1 + x2 * (C2 + x2 * (C3 + x2 * (C4 + x2 * (C5 + x2 * C6))))))
    # sin(x + 90° q) = s cos 90°q + c sin 90°q, cos(x + 90° q) = c cos 90°q - s sin 90°q, with
    # q in {-2, ..., 2}: cos 90°q = 1 - |q| and sin 90°q = 2q - q |q|, exact integers (never
    # -0.0), so every product and sum is exact (one term is 0) and no result is -0.0 (cos 90°
    # is +0). Arithmetic, not selects: 8 operations instead of 14, the loops' largest share.
    aq = abs(q)
    cq = 1.0 - aq
    sq = (q + q) - q * aq
    return s * cq + c * sq, c * cq - s * sq


@numba.njit(nogil=True, error_model="numpy", fastmath={"contract"})
def directions_deg(theta_l, phi_l, theta_v, phi_v, w, b0, n):
    # l and v of pairs b0 ... b0 + n - 1 into w[0:3, :n], w[3:6, :n]: arithmetic only,
    # which the compiler vectorises; "contract" lets it fuse the polynomials' multiply-adds
    # (one rounding instead of two; nothing else here has an add after a multiply). b0 and
    # n are unsigned (see f_deg_loop): an index b0 + k cannot be negative, so no wrap-around.
    for k in range(n):
        i = b0 + k
        st, ct = sincos_deg(theta_l[i], -0.0)
        sp, cp = sincos_deg(phi_l[i], -0.0)
        w[0, k] = st * cp
        w[1, k] = st * sp
        w[2, k] = ct
        st, ct = sincos_deg(theta_v[i], -0.0)
        sp, cp = sincos_deg(phi_v[i], -0.0)
        w[3, k] = st * cp
        w[4, k] = st * sp
        w[5, k] = ct


@numba.njit(nogil=True, error_model="numpy", fastmath={"contract"})
def directions_deg_isotropic(theta_l, phi_l, theta_v, phi_v, w, b0, n):
    # As directions_deg, both turned by -φ_v about the normal (v at φ = 0): three sin/cos
    # pairs instead of four. For an isotropic NDF (α_x = α_y) f is unchanged by the turn:
    # every other term reads heights, l·v, v·h and |l × v| (the direction-correlated λ(φ)).
    # φ_l - φ_v is kept exact: d + e with e its rounding error (Knuth's TwoSum: sums only,
    # which "contract" leaves alone), e added after the reduction in sincos_deg. Against
    # numpy's f on unturned directions (GGX, 2·10^5 pairs) the largest relative difference
    # is then that of the unturned loop (6.5e-14 at α = 0.3, 2.4e-13 at 0.02; unturned 6.9e-14,
    # 3.0e-13); rounding d instead doubled it (1.1e-13, 6.2e-13).
    for k in range(n):
        i = b0 + k
        a, b = phi_l[i], -phi_v[i]
        d = a + b
        b_virtual = d - a
        e = (a - (d - b_virtual)) + (b - b_virtual)
        st, ct = sincos_deg(theta_l[i], -0.0)
        sp, cp = sincos_deg(d, e)
        w[0, k] = st * cp
        w[1, k] = st * sp
        w[2, k] = ct
        st, ct = sincos_deg(theta_v[i], -0.0)
        w[3, k] = st
        w[4, k] = 0.0
        w[5, k] = ct


