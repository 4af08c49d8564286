"""The terms of the BRDF as shader functions: a dispatcher that knows no model by name.

Every registry entry writes its formula once (``D_formula``, ``mu_Lambda_formula`` of an
NDF; ``formula`` of a masking, G2 form and λ(φ); ``F_formula`` of a Fresnel model;
``f_formula`` of a diffuse model; app/physics/formula.py). Here each is emitted as one
shader function of its arguments and its parameters ``p``, and wrapped for lobe ``k``
(1 or 2) with the lobe's values as named constants (``NDF1_GAMMA``) — or uniforms, in
the parameterised form. An entry without a formula has no shader form: a
:class:`~app.errors.ParameterError` naming the parameter (HTTP 422), never a 500.
Every function works in the local frame n = +z, t = +x (direction of α_x), b = +y.
"""
from __future__ import annotations

from dataclasses import dataclass, field, replace

from ..errors import ParameterError
from ..physics.formula import Formula
from .lambda_fit import DEGREE, PIECES, lambda_fit
from .dsl import Const, Fn


@dataclass
class Terms:
    """Constants (``material``: a uniform in the parameterised form), tables and
    functions; names shared by two lobes are written once."""
    consts: list[Const] = field(default_factory=list)
    tables: list = field(default_factory=list)
    fns: list[Fn] = field(default_factory=list)
    material: set = field(default_factory=set)      # names of the material's parameters
    tabulated: list = field(default_factory=list)   # (what, why): a table embedded

    def add(self, other: "Terms") -> None:
        self.consts += other.consts
        self.tables += other.tables
        self.fns += other.fns
        self.material |= other.material
        self.tabulated += other.tabulated


def formula_fn(formula: Formula) -> Fn:
    """The formula as one shader function: its arguments, then its parameters p."""
    return Fn(formula.name, "float", [("float", a) for a in formula.args + formula.p],
              [("float", name, expr) for name, expr in formula.body], formula.result, formula.doc)


def formula_consts(formula: Formula) -> list[Const]:
    return [Const(name, value, why) for name, value, why in formula.consts]


def call(formula: Formula, args: list[str], prefix: str) -> str:
    """A call of the formula's function with ``args`` and the constants ``prefix_P``."""
    return f"{formula.name}({', '.join(list(args) + [param_name(prefix, p) for p in formula.p])})"


def param_name(prefix: str, p: str) -> str:
    return f"{prefix}_{p.upper()}"


def with_params(formula: Formula, prefix: str, values, what: str) -> Terms:
    """The function, its constants and the entry's values of p as named constants."""
    t = Terms(consts=formula_consts(formula), fns=[formula_fn(formula)])
    for i, p in enumerate(formula.p):
        name = param_name(prefix, p)
        t.consts.append(Const(name, float(values[i]), f"{p} of {what}"))
        t.material.add(name)
    return t


def used_params_only(formula: Formula, values) -> tuple[Formula, list]:
    """The formula without the parameters its expressions never read (GTR's D reads γ and
    ln D₀ of its six), and the values of those it keeps."""
    keep = [i for i, p in enumerate(formula.p) if formula.uses(p)]
    return replace(formula, p=tuple(formula.p[i] for i in keep)), [values[i] for i in keep]


def _refuse(param: str, value: str, what: str) -> ParameterError:
    return ParameterError(param, f"{param}={value} has no shader form: it declares no {what} "
                                 "(app/physics/formula.py), so /code cannot write it")


def alphas(k: int, ndf) -> Terms:
    t = Terms(consts=[Const(f"ALPHA_X{k}", ndf.alpha_x, f"α_x of lobe {k} (along t)"),
                      Const(f"ALPHA_Y{k}", ndf.alpha_y, f"α_y of lobe {k} (along b)")])
    t.material |= {f"ALPHA_X{k}", f"ALPHA_Y{k}"}
    return t


def ndf_D(k: int, ndf) -> Terms:
    """D_k(m): normalised so that ∫ D (n·m) dm = 1; 0 below the horizon."""
    formula = type(ndf).D_formula
    if formula is None:
        raise _refuse("ndf", ndf.name, "D_formula")
    t = alphas(k, ndf)
    formula, values = used_params_only(formula, ndf.kernel_params())
    t.add(with_params(formula, f"NDF{k}", values, f"the NDF of lobe {k}"))
    body = [("float", "mz", "Z(m)"),
            ("float", "q2", f"X(m) * X(m) / (ALPHA_X{k} * ALPHA_X{k}) + Y(m) * Y(m) / (ALPHA_Y{k} * ALPHA_Y{k})")]
    t.fns.append(Fn(f"D_{k}", "float", [("vec3", "m")], body,
                    f"sel(mz >= 0.0, {call(formula, ['mz', 'q2'], f'NDF{k}')} / (ALPHA_X{k} * ALPHA_Y{k}), 0.0)",
                    f"D of lobe {k} ({ndf.name}): the formula of α_x α_y D over α_x α_y, 0 below the horizon."))
    return t


def mu_Lambda(k: int, ndf, masking, fits: dict) -> Terms:
    """muLambda_k(w) = μΛ(ω), finite everywhere (Heitz 2014, eq. 43); s2 = s², s = α(φ) sinθ.

    The masking's own formula if it has one (an approximation); else the exact Smith μΛ:
    the NDF's formula where that is the exact one, else a compact fit of the Smith
    integral (lambda_fit.py), shared with an earlier lobe of the same shape (``fits``)."""
    body = [("float", "mu", "max(Z(w), 0.0)"),
            ("float", "s2", f"ALPHA_X{k} * ALPHA_X{k} * X(w) * X(w) + ALPHA_Y{k} * ALPHA_Y{k} * Y(w) * Y(w)")]
    ndf_formula = type(ndf).mu_Lambda_formula
    exact = masking.exact(ndf) is masking
    t = alphas(k, ndf)
    if masking.formula is not None:
        body.append(("float", "sin_t", "sqrt(X(w) * X(w) + Y(w) * Y(w))"))
        t.add(with_params(masking.formula, f"MASK{k}", masking.kernel_params(ndf), f"the masking of lobe {k}"))
        result, doc = call(masking.formula, ["mu", "s2", "sin_t"], f"MASK{k}"), f"μΛ of lobe {k}: masking={masking.name}."
    elif ndf_formula is not None and (masking.uses_ndf_Lambda or (exact and type(ndf).smith_exact)):
        t.add(with_params(ndf_formula, f"NDF{k}", ndf.kernel_params(), f"the NDF of lobe {k}"))
        result, doc = call(ndf_formula, ["mu", "s2"], f"NDF{k}"), f"μΛ of lobe {k}: the NDF's Smith Λ times μ."
    elif masking.uses_ndf_Lambda or exact:
        consts, tables, doc, fit_body, result, error, helper = lambda_fit(k, ndf, fits)
        t.consts += consts
        t.tables += tables
        t.fns.append(helper)
        body += fit_body
        t.tabulated.append((f"muLambda_{k}", f"{ndf.name}'s Smith Λ has no closed form in a shading language: "
                                             f"{PIECES} Chebyshev pieces of degree {DEGREE} in ln a fitted to the "
                                             "project's table of the Smith integral", error))
    else:
        raise _refuse("masking", masking.name, "formula")
    t.fns.append(Fn(f"muLambda_{k}", "float", [("vec3", "w")], body, result, doc))
    return t


def visibility(k: int, g2, ndf, lam: str) -> Terms:
    """V_k = G2/(4 μ_l μ_v) from μ ≥ 0 and μΛ of both directions; +∞ where it diverges.
    ``lam``: λ(φ) as an expression of phi (lambda_phi_call), or "0.0"."""
    if g2.formula is None:
        raise _refuse("g2", g2.name, "formula")
    t = with_params(g2.formula, f"G2_{k}", g2.kernel_params(ndf), f"the G2 form of lobe {k}")
    t.fns.append(Fn(f"V_{k}", "float", [("float", "mu_l"), ("float", "mu_v"), ("float", "ml_l"),
                                        ("float", "ml_v"), ("float", "phi")], [],
                    call(g2.formula, ["mu_l", "mu_v", "ml_l", "ml_v", lam], f"G2_{k}"),
                    f"V = G2/(4 μ_l μ_v) of lobe {k}: g2={g2.name}."))
    return t


def lambda_phi(entry) -> Terms:
    """λ(φ) of the direction-correlated forms, φ ∈ [0, π] the azimuth difference: the
    entry's formula, called by V_k (lambda_phi_call)."""
    if entry is None or entry.formula is None:
        raise _refuse("lambda_phi", getattr(entry, "name", "?"), "formula")
    return with_params(entry.formula, "LAMBDA_PHI", (), "λ(φ)")


def lambda_phi_call(entry) -> str:
    return call(entry.formula, ["phi"], "LAMBDA_PHI")


def fresnel(channels: list) -> Terms:
    """F(cos θ_d) per RGB channel, each channel a Fresnel model of the same class."""
    formula = type(channels[0]).F_formula
    if formula is None:
        raise _refuse("fresnel", channels[0].name, "F_formula")
    t = Terms(consts=formula_consts(formula), fns=[formula_fn(formula)])
    parts = []
    for ch, model in zip("RGB", channels):
        values = model.kernel_params()
        names = []
        for i, p in enumerate(formula.p):
            name = f"{p.upper()}_{ch}"
            t.consts.append(Const(name, float(values[i]), f"{p}, channel {ch}"))
            t.material.add(name)
            names.append(name)
        parts.append(f"{formula.name}({', '.join(['cos_theta_d'] + names)})")
    t.fns.append(Fn("F", "vec3", [("float", "cos_theta_d")], [], f"vec3({', '.join(parts)})",
                    f"F(cos θ_d) per channel: fresnel={channels[0].name}."))
    return t


def diffuse(model) -> Terms:
    """fd(mu_l, mu_v, l·v): the diffuse term at ρ = KD."""
    formula = type(model).f_formula
    if formula is None:
        raise _refuse("diffuse", model.name, "f_formula")
    t = with_params(formula, "FD", model.kernel_params(), f"diffuse={model.name}")
    t.fns.append(Fn("fd", "float", [("float", "mu_l"), ("float", "mu_v"), ("float", "l_dot_v")], [],
                    call(formula, ["KD", "mu_l", "mu_v", "l_dot_v"], "FD"),
                    f"The diffuse term f_d(ρ = KD; l, v), no cosine: diffuse={model.name}."))
    return t
