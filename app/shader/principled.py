"""The principled BRDF (Burley 2012) as one program: ``brdf(n, l, v)`` returns f (RGB, no
cosine) of the lobes the model draws (its ``lobe`` option), each lobe combined from the
formulas its parts write once — the registry's GGX, Smith μΛ, G2 form, Schlick F, GTR and
diffuse model (app/physics), and the principled model's own colour, roughness and
subsurface formulas (app/principled/lobes.py) — never a second spelling.

Its parameters (base colour, roughness, metallic, …) are the program's uniforms in the
parameterised form, and everything derived from them (C_tint, C_spec0, C_sheen, α_x, α_y,
the clearcoat's GTR1 normalisation, Kulla-Conty's per-channel scale) is formed in the
shader, so one compiled program draws any material. Only Kulla-Conty's E(μ) stays baked
for one roughness (the cubic pieces at the lobe's α, read from the data texture,
texture.py). The options are the program's structure.
"""
from __future__ import annotations

from ..physics.diffuse import DIFFUSES
from ..physics.formula import Formula, tokens
from ..physics.fresnel import FRESNELS
from ..physics.g2 import G2_FORMS, V_FORMULAS
from ..physics.ndf import NDFS
from ..principled import lobes as P
from ..principled.params import PARAMS
from ..principled.spec import ROUGHNESS, material
from . import embed
from .common import (FLOAT32_NOTE, GEOMETRY, SPEC, guard_consts, half_note, unique_consts, unique_fns,
                     world_fn)
from .dsl import Const, Fn, Program
from .terms import formula_consts, formula_fn

#: The names the principled model takes: what :func:`accepts` looks for in a family.
NAMES = frozenset(["base_color", ROUGHNESS.name, *(p.name for p in PARAMS)])
CHANNELS = "RGB"
BAKED_KC = ("Kulla-Conty's E(μ) is for this roughness (the data texture's cubic pieces at its α)")
#: disney.brdf's base_color_space=srgb decoding exponent (app/principled/material.py GAMMA).
GAMMA = 2.2


def accepts(family) -> bool:
    """A family that takes the principled model's parameters (its own registry entry)."""
    return NAMES <= set(family.own_names())


def call(formula: Formula, args: list[str], p: dict | None = None) -> str:
    """The formula's function at ``args``, its parameters p bound by name to expressions."""
    p = p or {}
    return f"{formula.name}({', '.join(list(args) + [p[name] for name in formula.p])})"


def used_params_only(formula: Formula) -> Formula:
    """The formula with the parameters its expressions never read left out (GTR's D reads
    γ and ln D₀ of its six)."""
    from dataclasses import replace
    return replace(formula, p=tuple(name for name in formula.p if formula.uses(name)))


def _per_channel(name: str, expr: str) -> list[tuple[str, str, str]]:
    """One float per channel: ``expr`` with ``{c}`` the channel's letter (lower case)."""
    return [("float", f"{name}_{c.lower()}", expr.format(c=c.lower(), C=c)) for c in CHANNELS]


def _vec(name: str) -> str:
    return f"vec3({', '.join(f'{name}_{c.lower()}' for c in CHANNELS)})"


def assemble(spec, form: str):
    """(Program, info) of a principled model; ``form`` "uniform": its parameters as uniforms."""
    values = spec.values
    m = material(values)
    lobe = values["lobe"]
    shown = {name: lobe in ("all", name) for name in ("diffuse", "sheen", "specular", "clearcoat")}
    uniforms = {f"BASE_{c}": float(x) for c, x in zip(CHANNELS, values["base_color"])}
    uniforms.update({p.upper(): float(values[p]) for p in [ROUGHNESS.name, *(q.name for q in PARAMS)]})
    consts = guard_consts() + [Const(name, value, _doc(name), uniform=(form == "uniform"))
                               for name, value in uniforms.items()]
    ggx, g2 = NDFS["ggx"], G2_FORMS[values["principled_g2"]].formula
    schlick = FRESNELS["schlick"].F_formula
    formulas = [P.TINT_FORMULA, P.SPEC0_FORMULA, schlick]
    fns: list[Fn] = [SPEC]
    tables, baked, tabulated = [], {}, []
    decode = "pow(BASE_{C}, GAMMA)" if values["base_color_space"] == "srgb" else "BASE_{C}"
    if values["base_color_space"] == "srgb":
        consts.append(Const("GAMMA", GAMMA, "base_color_space=srgb: C = base^2.2 (disney.brdf's mon2lin)"))
    body = GEOMETRY + [("float", "l_dot_v", "dot(l, v)"),
                       ("float", "cos_d", "sqrt(clamp(0.5 * (1.0 + l_dot_v), 0.0, 1.0))"),
                       ("float", "w", call(schlick, ["cos_d"], {"f0": "0.0", "f90": "1.0", "fresnel_p": "5.0"}))]
    notes = {"cos_d": "cos θ_d = l·h = √((1 + l·v)/2)",
             "w": "(1 − cos θ_d)⁵: Schlick's F with F₀ = 0, F₉₀ = 1 (sheen, specular, clearcoat share it)"}
    body += _per_channel("c", decode)
    body += [("float", "lum", "0.3 * c_r + 0.6 * c_g + 0.1 * c_b")]
    notes["lum"] = "disney.brdf's luminance of the base colour (C_tint = C/lum)"
    body += _per_channel("tint", call(P.TINT_FORMULA, ["c_{c}", "lum"]))
    total = []
    if shown["diffuse"]:
        name, _, exprs = P.DIFFUSE_CHOICES[values["principled_diffuse"]]
        fd = DIFFUSES[name].f_formula
        formulas += [fd, P.SUBSURFACE_FORMULA]
        bound = {p: " ".join("ROUGHNESS" if t == "r" else t for t in tokens(e)) for p, e in zip(fd.p, exprs)}
        fns.append(Fn("diffuse_channel", "float", [("float", "rho"), ("float", "ml"), ("float", "mv"),
                                                   ("float", "l_dot_v"), ("float", "ss")],
                      [("float", "fd", call(fd, ["rho", "ml", "mv", "l_dot_v"], bound))],
                      "sel(rho > 0.0, sel(SUBSURFACE > 0.0, (1.0 - SUBSURFACE) * fd + SUBSURFACE * rho * ss, fd), 0.0)",
                      f"One channel of the diffuse lobe: mix(f_d(ρ), ρ·ss, subsurface), ρ inside the model "
                      f"(principled_diffuse={values['principled_diffuse']}); 0 where ρ = 0."))
        body += [("float", "ss", call(P.SUBSURFACE_FORMULA, ["ROUGHNESS", "ml", "mv", "l_dot_v"]))]
        body += _per_channel("fd", "diffuse_channel((1.0 - METALLIC) * c_{c}, ml, mv, l_dot_v, ss)")
        total.append(_vec("fd"))
    if shown["sheen"]:
        formulas.append(P.SHEEN_COLOR_FORMULA)
        body += _per_channel("sh", f"(1.0 - METALLIC) * SHEEN * {call(P.SHEEN_COLOR_FORMULA, ['tint_{c}'], {'sheen_tint': 'SHEEN_TINT'})} * w")
        total.append(_vec("sh"))
    if shown["specular"]:
        formulas += [P.ALPHA_X_FORMULA, P.ALPHA_Y_FORMULA, ggx.D_formula, ggx.mu_Lambda_formula, g2]
        spec0 = {"metallic": "METALLIC", "specular": "SPECULAR", "specular_tint": "SPECULAR_TINT"}
        body += _per_channel("c0", call(P.SPEC0_FORMULA, ["c_{c}", "tint_{c}"], spec0))
        body += [("float", "ax", call(P.ALPHA_X_FORMULA, ["ROUGHNESS", "ANISOTROPIC"])),
                 ("float", "ay", call(P.ALPHA_Y_FORMULA, ["ROUGHNESS", "ANISOTROPIC"])),
                 ("float", "q2", "X(h) * X(h) / (ax * ax) + Y(h) * Y(h) / (ay * ay)"),
                 ("float", "Ds", f"sel(Z(h) >= 0.0, {call(ggx.D_formula, ['Z(h)', 'q2'])} / (ax * ay), 0.0)"),
                 ("float", "s2_l", "ax * ax * X(l) * X(l) + ay * ay * Y(l) * Y(l)"),
                 ("float", "s2_v", "ax * ax * X(v) * X(v) + ay * ay * Y(v) * Y(v)"),
                 ("float", "Vs", call(g2, ["ml", "mv", call(ggx.mu_Lambda_formula, ["ml", "s2_l"]),
                                           call(ggx.mu_Lambda_formula, ["mv", "s2_v"]), "0.0"]))]
        notes.update(Ds="GGX's D at h (Walter et al. 2007)", Vs=f"G2/(4 μ_l μ_v): g2={values['principled_g2']}, Smith GGX μΛ")
        body += _per_channel("sp", f"spec(Ds, {call(schlick, ['cos_d'], {'f0': 'c0_{c}', 'f90': '1.0', 'fresnel_p': '5.0'})}, Vs, h_ok)")
        total.append(_vec("sp"))
        if values["principled_multiscatter"] == "kulla_conty":
            term = m.multiscatter()[0].lobes[0]       # the channels share the table and α
            c, tab, e_fns = embed.kulla_conty_E(1, term, 0)
            consts += c + [Const("E_AVG_1", term.E_avg, "E_avg of the GGX lobe (F = 1) at the baked roughness"),
                           Const("ALPHA_X1", float(term.alpha), "α at the baked roughness (E's slice)")]
            tables += tab
            fns.extend(e_fns)
            f_avg = FRESNELS["schlick"].F_avg_formula
            formulas += [f_avg, P.KC_SCALE_FORMULA]
            body += [("float", "ms", "(1.0 - E_1(ml)) * (1.0 - E_1(mv))")]
            body += _per_channel("kc", f"{call(P.KC_SCALE_FORMULA, [call(f_avg, [], {'f0': 'c0_{c}', 'f90': '1.0', 'fresnel_p': '5.0'}), 'E_AVG_1'])} * ms")
            total.append(_vec("kc"))
            baked = {"ROUGHNESS": BAKED_KC, "ANISOTROPIC": BAKED_KC}
            tabulated.append(("E_1", "Kulla-Conty's E(μ) at the lobe's α, the cubic pieces of the project's "
                                     "E(μ, α) spline", term.table.error))
    if shown["clearcoat"]:
        gtr = NDFS["gtr"]
        d_gtr, sep = used_params_only(gtr.D_formula), V_FORMULAS["separable"]
        formulas += [P.CLEARCOAT_ALPHA_FORMULA, gtr.log_d0_formula, d_gtr, ggx.mu_Lambda_formula, sep]
        consts += [Const("CLEARCOAT_MASKING_ALPHA", P.CLEARCOAT_MASKING_ALPHA, "the clearcoat's Smith GGX α (fixed: 0.25)"),
                   Const("CLEARCOAT_F0", P.CLEARCOAT_F0, "the clearcoat's F₀ (η = 1.5)")]
        body += [("float", "ac", call(P.CLEARCOAT_ALPHA_FORMULA, ["CLEARCOAT_GLOSS"])),
                 ("float", "Dc", f"sel(Z(h) >= 0.0, {call(d_gtr, ['Z(h)', '(X(h) * X(h) + Y(h) * Y(h)) / (ac * ac)'], {'gamma': '1.0', 'log_d0': call(gtr.log_d0_formula, ['ac', '1.0'])})} / (ac * ac), 0.0)"),
                 ("float", "Vc", call(sep, ["ml", "mv",
                                            call(ggx.mu_Lambda_formula, ["ml", "CLEARCOAT_MASKING_ALPHA * CLEARCOAT_MASKING_ALPHA * (X(l) * X(l) + Y(l) * Y(l))"]),
                                            call(ggx.mu_Lambda_formula, ["mv", "CLEARCOAT_MASKING_ALPHA * CLEARCOAT_MASKING_ALPHA * (X(v) * X(v) + Y(v) * Y(v))"]),
                                            "0.0"])),
                 ("float", "cc", f"0.25 * CLEARCOAT * spec(Dc, CLEARCOAT_F0 + (1.0 - CLEARCOAT_F0) * w, Vc, h_ok)")]
        notes.update(Dc="GTR1 (GTR at γ = 1) of α = mix(0.1, 0.001, gloss)", Vc="separable Smith of a GGX, α = 0.25",
                     cc="0.25 clearcoat D F V, F = Schlick(0.04)")
        total.append("splat(cc)")
    body.append(("vec3", "f", " + ".join(total) if total else "splat(0.0)"))
    fns.append(Fn("brdf_local", "vec3", [("vec3", "l"), ("vec3", "v")], body,
                  "sel3(and_(mu_l >= 0.0, mu_v >= 0.0), sel3(ml + mv > 0.0, min(f, splat(F_MAX)), splat(F_MAX)), splat(0.0))",
                  f"f(l, v) of the principled BRDF (Burley 2012), lobe={lobe}: diffuse + sheen + specular + clearcoat,\n"
                  "RGB, no cosine; l, v unit vectors in the local frame (n = +z, t = +x), away from the surface;\n"
                  "0 unless both are in the closed upper hemisphere; F_MAX where both lie on the horizon\n"
                  "(f diverges there), so f·cos θ is 0 there.", notes))
    fns.append(world_fn())
    for formula in formulas:
        consts += formula_consts(formula)
    fns = unique_fns([formula_fn(f) for f in formulas]) + fns
    baked = baked if form == "uniform" else {}
    consts = [c if c.name not in baked else Const(c.name, c.value, c.comment) for c in consts]
    info = {"uniforms": {c.name: c.value for c in consts if c.uniform}, "baked": dict(sorted(baked.items())),
            "tabulated": tabulated, "precision": precision_notes(m)}
    return Program(_header(spec, values), unique_consts(consts), tables, unique_fns(fns), texture=bool(tables)), info


def _doc(name: str) -> str:
    if name.startswith("BASE_"):
        return f"base colour, channel {name[-1]} (linear unless base_color_space=srgb), [0, 1]"
    return f"{name.lower()}, [0, 1] (Burley 2012)"


def precision_notes(m) -> list[str]:
    notes = list(FLOAT32_NOTE)
    notes.append(half_note("the specular lobe", m.specular_brdf(FRESNELS["none"]()).ndf))
    if m.clearcoat:
        notes.append(half_note("the clearcoat lobe", m.clearcoat_ndf()))
    return notes


def _header(spec, values) -> list[str]:
    from .. import __version__
    query = "&".join(f"{k}={v}" for k, v in spec.as_query().items())
    return [f"BRDF Lobe Explorer {__version__}: generated code for the principled BRDF (Burley 2012).",
            f"Model: {query}",
            "f = diffuse + sheen + specular + clearcoat (the lobes the model's lobe option draws), RGB, no cosine:",
            "each lobe from the formulas of the registry's parts (GGX, Smith, the G2 forms, Schlick, GTR, the",
            "diffuse models: app/physics) and the principled model's own (app/principled/lobes.py).",
            "brdf(n, l, v): world space, any unit n; brdf_local: local frame n = +z, t = +x (α_x along t).",
            *(f"Precision: {line}" for line in precision_notes(material(values))),
            "Regenerate it with GET /api/v1/code?lang=...&" + query]
