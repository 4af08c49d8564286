"""A compact fit of the Smith μΛ where it has no closed form in a shading language
(GTR, exponential power, Student-t, and any NDF under masking=smith_numeric).

h(a) = μΛ/s of the project's table of the Smith integral (app/physics/smith_table.py,
|ΔG1| ≤ 1e-9) is fitted in x = ln a over the table's range [A_MIN, A_MAX] by PIECES
Chebyshev series of degree DEGREE, one per equal piece in x (h is analytic in ln a, so
a series converges geometrically: 24 pieces of width 1.1 at degree 10 reach |ΔG1| ≤ 6e-8
on the shapes tried — GTR γ 0.5-10, Student-t γ 1.51-1000, Blinn-Phong, exponential power
p ≤ 1.5 — and 1.5e-6 at exponential power p = 4, the end of its range; 264 numbers instead
of the table's 8192). Evaluated by Clenshaw's recurrence, stable in float32.

Why 24 × 10 (16 × 16 before): a shader reads DEGREE + 1 coefficients per evaluation, four
evaluations a two-lobe pixel, and on the GPU each read costs (block.py): 24 × 10 reads 11
instead of 17, holds 264 numbers instead of 272, and its worst |ΔG1| is 1.5e-6 instead of
3.2e-6 (measured on the shapes above, both ends of each range). The two-lobe GTR's point-lit
256² sphere: 18.9 → 14.5 ms a frame (bench/gpu_sphere.py). The fit's own
error is measured at generation against the table on FIT_CHECK points and stated as the largest
|ΔG1| = |a/(a + h_fit) − a/(a + h_table)| (G1 = μ/(μ + s h) = a/(a + h)), to which the
table's 1e-9 adds. Outside [A_MIN, A_MAX] the table's own end laws are kept.
"""
from __future__ import annotations

import numpy as np

from ..physics import smith_table
from .dsl import Const, Fn, Table

PIECES, DEGREE = 24, 10
#: Coefficients below TRIM × |c_0| of their piece are written as 0 (shorter code): all
#: of them together change h by < DEGREE × TRIM relative, below float32's 6e-8; the
#: stated error is measured on the trimmed series.
TRIM = 1e-9
#: Points in x at which the fit is checked against the table (uniform, both ends).
FIT_CHECK = 20001


#: The fits made, by the table they fit (its identity: smith_table caches one table per
#: shape): a fit costs a Chebyshev interpolation and a check on FIT_CHECK points, and the
#: same shape is written for every model, form and language that uses it.
_FITS: dict[int, tuple] = {}


def fit(ndf):
    """(table, coefficients (PIECES, DEGREE + 1), x0, width, max |ΔG1| of the fit)."""
    table = smith_table.lambda_table(ndf)
    done = _FITS.get(id(table))
    if done is not None and done[0] is table:
        return done
    done = _FITS[id(table)] = _fit(table)
    return done


def _fit(table):
    x0, x1 = np.log(table.a_min), np.log(table.a_max)
    width = (x1 - x0) / PIECES
    coef = np.empty((PIECES, DEGREE + 1))
    for i in range(PIECES):
        lo = x0 + i * width
        series = np.polynomial.chebyshev.Chebyshev.interpolate(
            lambda x: table.h(np.exp(x)), DEGREE, domain=[lo, lo + width])
        coef[i] = np.where(np.abs(series.coef) < TRIM * abs(series.coef[0]), 0.0, series.coef)
    x = np.linspace(x0, x1, FIT_CHECK)
    a = np.exp(x)
    i = np.clip(np.floor((x - x0) / width), 0, PIECES - 1).astype(int)
    t = 2.0 * (x - x0 - i * width) / width - 1.0
    h_fit = np.empty_like(x)
    for piece in range(PIECES):
        at = i == piece
        h_fit[at] = np.polynomial.chebyshev.chebval(t[at], coef[piece])
    h_tab = table.h(a)
    error = float(np.max(np.abs(a / (a + h_fit) - a / (a + h_tab))))
    return table, coef, x0, width, error


def lambda_fit(k: int, ndf, parts: dict):
    """(constants, tables, doc, body, result) of μΛ = s h(μ/s) by the fit; the doc and
    the returned error (last) state its largest |ΔG1| against the table. ``parts``: the
    program's fits so far (table identity → offset in LAM_C): two lobes of one shape (a
    shape-invariant NDF at two α) read one set of coefficients, written once."""
    table, coef, x0, width, error = fit(ndf)
    total = error + smith_table.TABLE_G1_ERROR
    n = DEGREE + 1
    shared = id(table) in parts
    base = parts[id(table)] if shared else PIECES * n * len(parts)
    parts[id(table)] = base
    j = base // (PIECES * n) + 1          # the shape's number in this program
    # the fit's range is the table's, the same for every shape: one set of constants
    consts = [Const("LAM_X0", x0, f"ln a of the fit's start (a = {table.a_min:g})"),
              Const("LAM_W", width, f"width in ln a of each of the {PIECES} pieces"),
              Const("LAM_A_MIN", table.a_min, "below: linear to the exact grazing value h(0)"),
              Const("LAM_A_MAX", table.a_max, "above: h(A_MAX) A_MAX/a (the tail law)"),
              Const(f"LAM_H0_{j}", table.h0, f"h(0) of shape {j} (lobe {k}), the grazing limit of μΛ/s")]
    tables = [] if shared else [Table("LAM_C", coef.ravel().tolist(),
                    f"h(a) = μΛ/s: Chebyshev coefficients c_0..c_{DEGREE} of each of {PIECES} pieces in x = ln a "
                    f"(a shape's piece i: {n} entries from the shape's offset + {n} i), t = 2(x − X0 − i W)/W − 1.",
                    offset=base)]
    doc = (f"μΛ = s h(a), a = μ/s, h of the general Smith integral (Heitz 2014, eq. 43) by {PIECES} Chebyshev\n"
           f"pieces of degree {DEGREE} in ln a: |ΔG1| ≤ {total:.1e} against the integral (fit {error:.1e}).")
    body = [("float", "s", "sqrt(s2)"), ("float", "a", "mu / max(s, 1e-30)"),
            ("float", "h", f"smith_fit_h(a, {base}, LAM_X0, LAM_W, LAM_A_MIN, LAM_A_MAX, LAM_H0_{j})")]
    return consts, tables, doc, body, "sel(s > 0.0, s * h, 0.0)", total, clenshaw()


def clenshaw() -> Fn:
    """h(a) from the pieces of one lobe (from ``base`` in LAM_C), shared by both lobes:
    Clenshaw's recurrence b_j = c_j + 2t b_{j+1} − b_{j+2}, h = c_0 + t b_1 − b_2; the
    table's end laws outside [A_MIN, A_MAX]."""
    n = DEGREE + 1
    body = [("float", "u", "log(clamp(a, a_min, a_max)) - x0"),
            ("int", "i", f"clamp(toint(floor(u / w)), 0, {PIECES - 1})"),
            ("int", "o", f"toint(base) + i * {n}"),   # toint: the Python form passes floats
            ("float", "t", "2.0 * (u - tofloat(i) * w) / w - 1.0"),
            ("float", "t2", "2.0 * t")]
    prev, prev2 = "0.0", "0.0"
    for j in range(DEGREE, 0, -1):
        body.append(("float", f"b{j}", f"LAM_C[o + {j}] + t2 * {prev} - {prev2}"))
        prev2, prev = prev, f"b{j}"
    body.append(("float", "h_in", f"LAM_C[o] + t * b1 - {prev2}"))
    return Fn("smith_fit_h", "float",
              [("float", "a"), ("int", "base"), ("float", "x0"), ("float", "w"), ("float", "a_min"),
               ("float", "a_max"), ("float", "h0")], body,
              "sel(a < a_min, h0 + (h_in - h0) * (a / a_min), sel(a > a_max, h_in * (a_max / a), h_in))",
              f"h(a) = μΛ/s by {PIECES} Chebyshev pieces of degree {DEGREE} in x = ln a (one lobe's, from base in\n"
              "LAM_C); below A_MIN linear to the grazing limit h(0), above A_MAX the tail law h(A_MAX) A_MAX/a\n"
              "(h_in: the fit at a clamped to [A_MIN, A_MAX]).")
