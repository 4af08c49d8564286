"""A compact fit of the Smith μΛ where it has no closed form in a shading language
(GTR, exponential power, Student-t, and any NDF under masking=smith_numeric).

h(a) = μΛ/s of the project's table of the Smith integral (app/physics/smith_table.py,
|ΔG1| ≤ 1e-9) is fitted in x = ln a over the table's range [A_MIN, A_MAX] by PIECES
Chebyshev series of degree DEGREE, one per equal piece in x (h is analytic in ln a, so
a series converges geometrically: 16 pieces of width 1.7 at degree 16 reach
|ΔG1| ≤ 3e-8 on every registered shape tried, 272 numbers instead of the table's 8192). Evaluated by Clenshaw's recurrence, stable in float32. The fit's own error is
measured at generation against the table on FIT_CHECK points and stated as the largest
|ΔG1| = |a/(a + h_fit) − a/(a + h_table)| (G1 = μ/(μ + s h) = a/(a + h)), to which the
table's 1e-9 adds. Outside [A_MIN, A_MAX] the table's own end laws are kept.
"""
from __future__ import annotations

import numpy as np

from ..physics import smith_table
from .dsl import Const, Table

PIECES, DEGREE = 16, 16
#: Points in x at which the fit is checked against the table (uniform, both ends).
FIT_CHECK = 20001


def fit(ndf):
    """(table, coefficients (PIECES, DEGREE + 1), x0, width, max |ΔG1| of the fit)."""
    table = smith_table.lambda_table(ndf)
    x0, x1 = np.log(table.a_min), np.log(table.a_max)
    width = (x1 - x0) / PIECES
    coef = np.empty((PIECES, DEGREE + 1))
    for i in range(PIECES):
        lo = x0 + i * width
        series = np.polynomial.chebyshev.Chebyshev.interpolate(
            lambda x: table.h(np.exp(x)), DEGREE, domain=[lo, lo + width])
        coef[i] = series.coef
    x = np.linspace(x0, x1, FIT_CHECK)
    a = np.exp(x)
    i = np.clip(np.floor((x - x0) / width), 0, PIECES - 1).astype(int)
    t = 2.0 * (x - x0 - i * width) / width - 1.0
    h_fit = np.array([np.polynomial.chebyshev.chebval(tt, coef[ii]) for tt, ii in zip(t, i)])
    h_tab = table.h(a)
    error = float(np.max(np.abs(a / (a + h_fit) - a / (a + h_tab))))
    return table, coef, x0, width, error


def lambda_fit(k: int, ndf):
    """(constants, tables, doc, body, result) of μΛ = s h(μ/s) by the fit; the doc and
    the returned error (last) state its largest |ΔG1| against the table."""
    table, coef, x0, width, error = fit(ndf)
    total = error + smith_table.TABLE_G1_ERROR
    consts = [Const(f"LAM_X0_{k}", x0, f"ln a of the fit's start (a = {table.a_min:g})"),
              Const(f"LAM_W_{k}", width, f"width in ln a of each of the {PIECES} pieces"),
              Const(f"LAM_A_MIN_{k}", table.a_min, "below: linear to the exact grazing value h(0)"),
              Const(f"LAM_A_MAX_{k}", table.a_max, "above: h(A_MAX) A_MAX/a (the tail law)"),
              Const(f"LAM_H0_{k}", table.h0, "h(0), the grazing limit of μΛ/s"),
              Const(f"LAM_HMIN_{k}", table.h_min, "h(A_MIN)")]
    n = DEGREE + 1
    tables = [Table(f"LAM_C_{k}", coef.ravel().tolist(),
                    f"h(a) = μΛ/s of {ndf.name}: Chebyshev coefficients c_0..c_{DEGREE} of each of {PIECES} pieces "
                    f"in x = ln a (piece i: {n} entries from {n}·i), t = 2(x − X0 − i W)/W − 1.")]
    doc = (f"μΛ = s h(a), a = μ/s, h of the general Smith integral (Heitz 2014, eq. 43) by {PIECES} Chebyshev\n"
           f"pieces of degree {DEGREE} in ln a: |ΔG1| ≤ {total:.1e} against the integral (fit {error:.1e}).")
    body = [("float", "a", "mu / max(s, 1e-30)"),
            ("float", "u", f"log(clamp(a, LAM_A_MIN_{k}, LAM_A_MAX_{k})) - LAM_X0_{k}"),
            ("int", "i", f"clamp(toint(floor(u / LAM_W_{k})), 0, {PIECES - 1})"),
            ("int", "o", f"i * {n}"),
            ("float", "t", f"2.0 * (u - tofloat(i) * LAM_W_{k}) / LAM_W_{k} - 1.0"),
            ("float", "t2", "2.0 * t")]
    # Clenshaw: b_j = c_j + 2t b_{j+1} − b_{j+2}, h = c_0 + t b_1 − b_2
    prev, prev2 = "0.0", "0.0"
    for j in range(DEGREE, 0, -1):
        body.append(("float", f"b{j}", f"LAM_C_{k}[o + {j}] + t2 * {prev} - {prev2}"))
        prev2, prev = prev, f"b{j}"
    body += [("float", "h_in", f"LAM_C_{k}[o] + t * b1 - {prev2}"),
             ("float", "h", f"sel(a < LAM_A_MIN_{k}, LAM_H0_{k} + (LAM_HMIN_{k} - LAM_H0_{k}) * (a / LAM_A_MIN_{k}),"
                            f" sel(a > LAM_A_MAX_{k}, h_in * (LAM_A_MAX_{k} / a), h_in))")]
    return consts, tables, doc, body, "sel(s > 0.0, s * h, 0.0)", total
