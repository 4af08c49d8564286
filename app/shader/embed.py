"""The project's tables, embedded in generated code as arrays.

* Smith μΛ without a closed form in a shading language — GTR and exponential power (the
  project's own table of the Smith integral, app/physics/smith_table.py), Student-t (its
  closed form needs the incomplete beta function: tabulated from that closed form) and
  every ``smith_numeric`` model but GGX and Beckmann — as h(a) = μΛ/s on the project's
  nodes uniform in ln a, with the PCHIP slopes: the cubic Hermite pieces are the
  interpolant itself, so no error is added to the table's own (|ΔG1| ≤ 1e-8).
* Kulla-Conty's E(μ) at the lobe's α: the bicubic spline of the E(μ, α) table
  (app/integrate/tables.py) restricted to that α is a cubic spline in y; its pieces
  are embedded as power-series coefficients on its breakpoints, again exact.
"""
from __future__ import annotations

import numpy as np
from scipy.interpolate import BSpline, PchipInterpolator, PPoly

from ..integrate import tables as etables
from ..physics import smith_table
from .dsl import Const, Fn, Table

CLOSED_FORMS = {"ggx": "ggx", "beckmann": "beckmann"}
APPROXIMATIONS = ("walter", "karis", "schlick_ibl", "schlick_direct")


def lambda_form(ndf, masking: str) -> str:
    """How μΛ is written: a closed form, an approximation, or which table."""
    if masking in APPROXIMATIONS:
        return masking
    if ndf.name in CLOSED_FORMS:
        return CLOSED_FORMS[ndf.name]
    if masking == "smith":
        if ndf.name == "blinn_phong":
            return "beckmann"          # Walter 2007's substitution: Beckmann's Λ at α_b
        return "table_closed" if ndf.name == "student_t" else "table_project"
    if masking == "smith_numeric":
        return "table_numeric"
    raise ValueError(f"no code for masking={masking}")


def _closed_form_table(ndf):
    """h(a) = μΛ(μ = a, s = 1) from the NDF's closed form, on smith_table's nodes."""
    a = np.exp(np.linspace(np.log(smith_table.A_MIN), np.log(smith_table.A_MAX), smith_table.TABLE_NODES))
    unit = type(ndf)(1.0, None, **{p.name: getattr(ndf, p.name) for p in ndf.shape_params})
    h = unit._mu_Lambda(a, np.ones_like(a))
    h = np.where(h < smith_table.H_FLUSH, 0.0, h)
    h0 = float(unit._mu_Lambda(np.zeros(1), np.ones(1))[0])
    return h0, float(h[0]), PchipInterpolator(np.log(a), h)


def _project_table(ndf):
    shape = tuple((p.name, getattr(ndf, p.name)) for p in ndf.shape_params)
    alpha = 1.0 if ndf.shape_invariant else ndf.alpha_x
    return smith_table._table(type(ndf), alpha, shape)


def lambda_table(k: int, ndf, form: str, lobe_brdf):
    """(constants, tables, doc, body, result) of μΛ = s h(μ/s) from a table of h in ln a."""
    h0, h_min, interp = _closed_form_table(ndf) if form == "table_closed" else _project_table(ndf)
    x = interp.x
    n = x.size
    dx = float(x[1] - x[0])
    values = interp(x)
    slopes = interp(x, 1) * dx           # dh/du with u = (ln a − ln a₀)/Δ
    source = {"table_closed": f"the closed form of {ndf.name} (Ribardière et al. 2017)",
              "table_project": "the general Smith integral (Heitz 2014, eq. 43), the project's table",
              "table_numeric": "the general Smith integral by quadrature (Heitz 2014, eq. 43)"}[form]
    scale = "" if ndf.shape_invariant else f" at α = {ndf.alpha_x:g} (not shape-invariant)"
    consts = [Const(f"LAM_LNA0_{k}", float(x[0]), f"ln a of the first node (a = {smith_table.A_MIN:g})"),
              Const(f"LAM_DLNA_{k}", dx, f"node spacing in ln a ({n} nodes)"),
              Const(f"LAM_A_MIN_{k}", smith_table.A_MIN, "below: linear to the exact grazing value h(0)"),
              Const(f"LAM_A_MAX_{k}", smith_table.A_MAX, "above: h(A_MAX) A_MAX/a (the r̃⁻⁴ tail law)"),
              Const(f"LAM_H0_{k}", h0, "h(0), the grazing limit of μΛ/s"),
              Const(f"LAM_HMIN_{k}", h_min, "h(A_MIN)")]
    tables = [Table(f"LAM_H_{k}", values.tolist(), f"h(a) = μΛ/s of {ndf.name}{scale} from {source}, "
                    f"at a = exp(LAM_LNA0_{k} + i LAM_DLNA_{k}); monotone cubic (PCHIP) between."),
              Table(f"LAM_M_{k}", slopes.tolist(), f"PCHIP slopes of LAM_H_{k} per node interval (dh/di).")]
    doc = (f"μΛ = s h(a), a = μ/s, h tabulated (below) from {source}; cubic Hermite in ln a,\n"
           f"the table's own interpolant: |ΔG1| ≤ 1e-8 against the integral.")
    body = [("float", "a", "mu / s"),
            ("float", "u", f"(log(clamp(a, LAM_A_MIN_{k}, LAM_A_MAX_{k})) - LAM_LNA0_{k}) / LAM_DLNA_{k}"),
            ("int", "i", f"clamp(toint(floor(u)), 0, {n - 2})"),
            ("float", "t", "u - tofloat(i)"),
            ("float", "h_in", f"(2.0 * t - 3.0) * t * t * (LAM_H_{k}[i] - LAM_H_{k}[i + 1]) + LAM_H_{k}[i]"
                              f" + t * (t - 1.0) * ((t - 1.0) * LAM_M_{k}[i] + t * LAM_M_{k}[i + 1])"),
            ("float", "h", f"sel(a < LAM_A_MIN_{k}, LAM_H0_{k} + (LAM_HMIN_{k} - LAM_H0_{k}) * (a / LAM_A_MIN_{k}),"
                           f" sel(a > LAM_A_MAX_{k}, h_in * (LAM_A_MAX_{k} / a), h_in))")]
    return consts, tables, doc, body, "sel(s > 0.0, s * h, 0.0)"


def kulla_conty_E(k: int, term) -> tuple[list, list, Fn]:
    """E_k(μ): the lobe's E(μ, α) table at its α, as the cubic pieces of its spline in y."""
    table = term.table
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
    tabs = [Table(f"KC_BP_{k}", bp.tolist(), f"breakpoints in y of E_{k}'s cubic pieces")]
    for j in range(4):
        tabs.append(Table(f"KC_C{j}_{k}", coeffs[j].tolist(),
                          f"coefficient of d^{3 - j} of each piece, d = y − KC_BP_{k}[j]"))
    body = [("float", "m", "clamp(mu, 0.0, 1.0)"),
            ("float", "ra", f"sqrt(m / (KC_ALPHA_{k} * sqrt((1.0 - m) * (1.0 + m))))"),
            ("float", "y", "sel(m < 1.0, ra / (1.0 + ra), 1.0)"),
            ("int", "j", f"clamp(toint(floor(KC_NM1_{k} * pow(y, KC_INV_GRADING))) - 1, 0, {m - 1})"),
            ("float", "d", f"y - KC_BP_{k}[j]"),
            ("float", "e", f"((KC_C0_{k}[j] * d + KC_C1_{k}[j]) * d + KC_C2_{k}[j]) * d + KC_C3_{k}[j]")]
    return consts, tabs, Fn(f"E_{k}", "float", [("float", "mu")], body, "clamp(e, 0.0, 1.0)", doc)
