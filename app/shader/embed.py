"""The project's tables, embedded in generated code as arrays.

* Smith μΛ without a closed form in a shading language — GTR and exponential power, and
  Student-t (its closed form needs the incomplete beta function) and every
  ``smith_numeric`` model but GGX and Beckmann — as the project's own table of the Smith
  integral (app/physics/smith_table.py): h(a) = μΛ/s, one cubic per interval uniform in
  ln a, its coefficients embedded as they are, so nothing is added to the table's error.
* Kulla-Conty's E(μ) at the lobe's α: the bicubic spline of the E(μ, α) table
  (app/integrate/tables.py) restricted to that α is a cubic spline in y; its pieces
  are embedded as power-series coefficients on its breakpoints, again exact.
"""
from __future__ import annotations

import numpy as np
from scipy.interpolate import CubicSpline, BSpline, PPoly

from ..integrate.tables import table as etables
from ..physics import smith_table
from .dsl import Const, Fn, Table

#: |ΔG1| of the embedded Smith table against the integral (app/physics/smith_table.py).
TABLE_ERROR = smith_table.TABLE_G1_ERROR

def lambda_table(k: int, ndf):
    """(constants, tables, doc, body, result) of μΛ = s h(μ/s) from the project's table
    of h in ln a (app/physics/smith_table.py): one cubic per interval, coefficients as
    the table holds them."""
    table = smith_table.lambda_table(ndf)
    c = table.coefficients
    n = c.shape[1]
    source = "the general Smith integral (Heitz 2014, eq. 43)"
    scale = "" if ndf.shape_invariant else f" at α = {ndf.alpha_x:g} (not shape-invariant)"
    consts = [Const(f"LAM_X0_{k}", table.x0, f"ln a of the first node (a = {table.a_min:g})"),
              Const(f"LAM_DX_{k}", table.dx, f"interval in ln a ({n} intervals)"),
              Const(f"LAM_A_MIN_{k}", table.a_min, "below: linear to the exact grazing value h(0)"),
              Const(f"LAM_A_MAX_{k}", table.a_max, "above: h(A_MAX) A_MAX/a (the r̃⁻⁴ tail law)"),
              Const(f"LAM_H0_{k}", table.h0, "h(0), the grazing limit of μΛ/s"),
              Const(f"LAM_HMIN_{k}", table.h_min, "h(A_MIN)")]
    tables = [Table(f"LAM_C{j}_{k}", c[j].tolist(),
                    (f"h(a) = μΛ/s of {ndf.name}{scale} from {source}: on interval i of x = ln a, "
                     f"h = ((C0 t + C1) t + C2) t + C3, t = x − LAM_X0_{k} − i LAM_DX_{k}. " if j == 0 else "")
                    + f"C{j} of each interval.") for j in range(4)]
    doc = (f"μΛ = s h(a), a = μ/s, h from {source}, tabulated in ln a\n"
           f"(value and exact slope at {n + 1} nodes, cubic Hermite): |ΔG1| ≤ {smith_table.TABLE_G1_ERROR:g} "
           "against the integral.")
    cf = [f"LAM_C{j}_{k}[i]" for j in range(4)]
    body = [("float", "a", "mu / s"),
            ("float", "u", f"(log(clamp(a, LAM_A_MIN_{k}, LAM_A_MAX_{k})) - LAM_X0_{k}) / LAM_DX_{k}"),
            ("int", "i", f"clamp(toint(floor(u)), 0, {n - 1})"),
            ("float", "t", f"(u - tofloat(i)) * LAM_DX_{k}"),
            ("float", "h_in", f"(({cf[0]} * t + {cf[1]}) * t + {cf[2]}) * t + {cf[3]}"),
            ("float", "h", f"sel(a < LAM_A_MIN_{k}, LAM_H0_{k} + (LAM_HMIN_{k} - LAM_H0_{k}) * (a / LAM_A_MIN_{k}),"
                           f" sel(a > LAM_A_MAX_{k}, h_in * (LAM_A_MAX_{k} / a), h_in))")]
    return consts, tables, doc, body, "sel(s > 0.0, s * h, 0.0)"


def _pieces(bp, coeffs, what: str, offset: int) -> list:
    """A lobe's cubic pieces of E as its part (from ``offset``) of the tables every lobe
    shares: breakpoints in y and the four coefficients of each piece."""
    tabs = [Table("KC_BP", list(bp), f"breakpoints in y of each lobe's cubic pieces of E{what}", offset=offset)]
    for j in range(4):
        tabs.append(Table(f"KC_C{j}", coeffs[j].tolist(),
                          f"coefficient of d^{3 - j} of each piece, d = y − KC_BP[j]", offset=offset))
    return tabs


def _y_of_mu(k: int) -> list:
    """y = √a/(1 + √a), a = μ/(α sinθ): the tables' variable (1 at normal incidence)."""
    return _y_of(f"KC_ALPHA_{k}")


def _y_of(alpha: str) -> list:
    return [("float", "m", "clamp(mu, 0.0, 1.0)"),
            ("float", "ra", f"sqrt(m / ({alpha} * sqrt((1.0 - m) * (1.0 + m))))"),
            ("float", "y", "sel(m < 1.0, ra / (1.0 + ra), 1.0)")]


def _piece_at_j(var: str = "y") -> list:
    """The cubic of piece j (an index into the shared tables) at ``var`` (Horner)."""
    return [("float", "d", f"{var} - KC_BP[j]"),
            ("float", "e", "((KC_C0[j] * d + KC_C1[j]) * d + KC_C2[j]) * d + KC_C3[j]")]


def _slice_search(steps: int, graded: bool) -> Fn:
    """E(μ) of a slice whose padded part of 2^steps pieces starts at j0 in the shared
    tables (its last real piece j_last): the piece found by a branch-free binary search
    unrolled over the breakpoints (one ``sel`` a step); ``graded``: the pieces are in
    x = y^q. One function for every lobe of that search length."""
    params = [("float", "mu"), ("float", "alpha")] + ([("float", "q")] if graded else []) + \
        [("int", "first"), ("int", "last")]
    body = _y_of("alpha")
    var = "y"
    if graded:
        body.append(("float", "x", "pow(y, q)"))
        var = "x"
    body.append(("int", "j0", "toint(first)"))      # toint: the Python form passes floats
    for i in range(steps):
        step = 1 << (steps - 1 - i)
        body.append(("int", f"j{i + 1}", f"sel({var} >= KC_BP[j{i} + {step}], j{i} + {step}, j{i})"))
    body += [("int", "j", f"min(j{steps}, toint(last))")] + _piece_at_j(var)
    return Fn(f"kc_slice_E{steps}{'q' if graded else ''}", "float", params, body, "clamp(e, 0.0, 1.0)",
              f"E(μ) at F = 1 from a lobe's {1 << steps} padded cubic pieces in y = √a/(1 + √a), a = μ/(α sinθ)"
              + (", in x = y^q (where E is smooth at grazing)" if graded else "") + ",\nfrom index first (its last real piece: last) of KC_BP, "
              "KC_C0..KC_C3; the piece by a branch-free binary search.")


def slice_steps(term) -> int:
    """Binary-search steps over a lobe's slice pieces (0: not a slice, a whole table)."""
    spline = term.table.spline
    return max(1, int(np.ceil(np.log2(spline.x.size - 1)))) if isinstance(spline, CubicSpline) else 0


def _slice_E(k: int, term, offset: int, steps: int = 0) -> tuple[list, list, list]:
    """E_k(μ) from the per-α slice (integrate/tables/alpha_slice.py): its cubic pieces at
    adaptive breakpoints, read by the search function every lobe of its length shares;
    ``steps``: at least this search length (the program's lobes share one function)."""
    table = term.table
    bp, coeffs = table.spline.x[:-1], table.spline.c
    m = bp.size
    steps = max(steps, slice_steps(term))
    padded = np.concatenate([bp, np.full((1 << steps) - m, 2.0)])   # y ≤ 1 never passes 2
    consts = []                     # the slice is at the lobe's own α, ALPHA_X{k}
    doc = (f"E(μ) of lobe {k} at F = 1 (Kulla & Conty 2017): the project's E(μ) slice at α = {term.alpha:g}"
           f" ({m} pieces, reported error {table.error:.1e}).")
    graded = table.exponent != 1.0   # the slice's axis is x = y^q where E ~ μ^(2γ−3) at grazing
    args = ["mu", f"ALPHA_X{k}"]
    if graded:
        consts.append(Const(f"KC_Q_{k}", float(table.exponent), f"q of lobe {k}'s axis x = y^q"))
        args.append(f"KC_Q_{k}")
    search = _slice_search(steps, graded)
    coeffs = np.concatenate([coeffs, np.zeros((4, padded.size - m))], axis=1)   # the padding's pieces
    fn = Fn(f"E_{k}", "float", [("float", "mu")], [],
            f"{search.name}({', '.join(args)}, {offset}, {offset + m - 1})", doc)
    return consts, _pieces(padded.tolist(), coeffs, " (a slice's padded with 2)", offset), [search, fn]


def kulla_conty_E(k: int, term, offset: int = 0, steps: int = 0) -> tuple[list, list, list]:
    """E_k(μ): the lobe's E(μ, α) table at its α, as the cubic pieces of its spline in y,
    from ``offset`` in the tables the lobes share (the previous lobes' parts before it);
    the functions it needs, E_k last. ``steps``: a slice's search length at least."""
    table = term.table
    if isinstance(table.spline, CubicSpline):      # a slice at the lobe's own α
        return _slice_E(k, term, offset, steps)
    spline = table.spline
    tx, ty, c = spline.tck
    kx, ky = spline.degrees
    r = float(np.clip(np.sqrt(term.alpha), table.r[0], table.r[-1]))
    coef = c.reshape(len(tx) - kx - 1, len(ty) - ky - 1)
    cy = BSpline.design_matrix(np.array([r]), tx, kx).toarray()[0] @ coef
    pp = PPoly.from_spline(BSpline(ty, cy, ky))
    keep = np.diff(pp.x) > 0
    bp, coeffs = pp.x[:-1][keep], pp.c[:, keep]
    n = table.y.size
    expected = np.concatenate([[table.y[0]], table.y[2:-2]])   # FITPACK's interpolating knots
    if bp.size != expected.size or not np.allclose(bp, expected, rtol=0, atol=1e-15):
        raise ValueError("unexpected knots of the E(μ, α) spline: cannot index them directly")
    m = bp.size
    alpha = float(np.clip(term.alpha, table.r[0] ** 2, 1.0))
    consts = [Const(f"KC_ALPHA_{k}", alpha, f"α of lobe {k} as the table reads it"),
              Const(f"KC_NM1_{k}", n - 1.0, "y nodes are (j/KC_NM1)^1.5 (graded towards grazing)"),
              Const("KC_INV_GRADING", 1.0 / etables.Y_GRADING, "1/1.5")]
    doc = (f"E(μ) of lobe {k} at F = 1 (Kulla & Conty 2017), from the project's {table.size} E(μ, α) table\n"
           f"(bicubic spline, reported error {table.error:.1e}) at α = {term.alpha:g}: y = √a/(1 + √a), a = μ/(α sinθ).")
    tabs = _pieces(bp.tolist(), coeffs, "", offset)
    body = _y_of_mu(k) + [
        ("int", "j", f"{offset} + clamp(toint(floor(KC_NM1_{k} * pow(y, KC_INV_GRADING))) - 1, 0, {m - 1})")
    ] + _piece_at_j()
    return consts, tabs, [Fn(f"E_{k}", "float", [("float", "mu")], body, "clamp(e, 0.0, 1.0)", doc)]
