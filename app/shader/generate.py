"""The configured model as one self-contained program: GLSL, HLSL or Python (numpy).

``brdf(n, l, v)`` returns f (RGB, no cosine) with l and v pointing away from the surface;
it builds the project's tangent frame (t = +x projected onto the tangent plane, b = n × t)
and calls ``brdf_local``. ``D``, ``G1``, ``G2`` and ``F`` are the helpers, in the local
frame n = +z. The terms are those of app/physics (terms.py, embed.py).
"""
from __future__ import annotations

import functools
import math
from dataclasses import replace

import numpy as np

from .. import __version__
from ..errors import ParameterError
from ..integrate.compensation import KullaConty, kulla_conty
from ..model import ModelSpec
from ..physics.diffuse.lambert import Lambert
from ..physics.formula import tokens
from ..physics.g2 import lambda_phi_entry
from . import block, embed, principled, terms, texture
from .dsl import Const, Fn, Program, Table
from .emit import write
from .library import ERFCX_MAX_RELATIVE_ERROR, LIBRARY

from .common import (F_MAX, FRAME_MIN, HALF_VECTOR_MIN_NORM, SPEC, GEOMETRY, guard_consts,  # noqa: F401
                     FLOAT32_NOTE, half_note, unique_consts, unique_fns, world_fn)


def model_query(spec: ModelSpec) -> str:
    """The query string that reproduces the model (derived values left out)."""
    derived = set(getattr(spec.brdf().ndf, "derived_doc", {}) or {})
    if spec.values.get("material"):
        derived.add("fresnel")               # set by the material
    return "&".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}"
                    for k, v in spec.values.items() if v is not None and k not in derived)


#: The forms of /code: a snapshot (every parameter a constant) or parameterised
#: (the material's parameters as uniforms, each with its default value).
FORMS = ("const", "uniform")
BAKED_TABLE = "the embedded fit of the Smith integral is for this value"
BAKED_KC = ("Kulla-Conty's E(μ) (the data texture's cubic pieces, at the lobe's α) and its scale are "
            "for this value")


def fresnel_channels(fresnel) -> list:
    """Each RGB channel's Fresnel model (three equal ones for a scalar Fresnel)."""
    return list(getattr(fresnel, "channels", None) or [fresnel] * 3)


def program(spec: ModelSpec, form: str = "const") -> Program:
    """The model as a Program; ``form="uniform"``: the material's parameters (α, the
    NDF's shape, F₀/F₉₀ or η/κ per channel, k_d, the lobe weights) as uniforms."""
    return _assemble(spec, form)[0]


def _writes_microfacet(family) -> bool:
    """A family that takes a microfacet model's choices (NDF, masking, G2, Fresnel, diffuse)."""
    known = _MICROFACET.get(id(family))
    if known is None or known[0] is not family:
        known = _MICROFACET[id(family)] = (family, "ndf" in family.own_names())
    return known[1]


#: Whether a family takes the microfacet choices, by family (own_names builds its fields).
_MICROFACET: dict[int, tuple] = {}


#: The writers, each (whether it writes a family, its assemble(spec, form) → (Program, info)).
WRITERS = ((_writes_microfacet, lambda spec, form: _assemble_microfacet(spec, form)),
           (principled.accepts, principled.assemble))


def writes(family) -> bool:
    """Whether the generator writes this model family (a microfacet model's choices, or the
    principled model's parameters); /models states it as ``shader``."""
    return any(accepts(family) for accepts, _ in WRITERS)


def _assemble(spec: ModelSpec, form: str):
    if form not in FORMS:
        raise ParameterError("form", f"form must be one of {', '.join(FORMS)}; got {form!r}")
    for accepts, assemble in WRITERS:
        if accepts(spec.family):
            return assemble(spec, form)
    raise ParameterError("model", f"code generation has no writer for model={spec.family.name}")


def _assemble_microfacet(spec: ModelSpec, form: str):
    brdf = spec.brdf()
    ms: KullaConty | None = getattr(brdf, "multiscatter", None)
    single = brdf.single() if ms is not None else brdf
    lobes = single.lobes()
    g2 = single.g2
    t = terms.Terms(consts=guard_consts() + [Const("KD", brdf.kd, "ρ, the weight of the diffuse term")])
    t.material.add("KD")
    baked: dict[str, str] = {}
    t.add(terms.fresnel(fresnel_channels(brdf.fresnel)))
    t.add(terms.diffuse(getattr(brdf, "diffuse", None) or Lambert()))
    lam = "0.0"
    if g2.needs_phi:
        t.add(terms.lambda_phi(lambda_phi_entry(single.lambda_phi)))
        lam = terms.lambda_phi_call(lambda_phi_entry(single.lambda_phi))
    fits: dict = {}                 # the Smith fits written so far (lobes of one shape share one)
    for k, (weight, lobe) in enumerate(lobes, start=1):
        t.consts.append(Const(f"W{k}", weight, f"weight of specular lobe {k}"))
        t.material.add(f"W{k}")
        t.add(terms.ndf_D(k, lobe.ndf))
        ml = terms.mu_Lambda(k, lobe.ndf, lobe.masking, fits)
        if ml.tabulated:
            baked.update({name: BAKED_TABLE for name in t.material if name.startswith(f"NDF{k}_")})
            if not getattr(lobe.ndf, "shape_invariant", True):
                baked.update({f"ALPHA_X{k}": BAKED_TABLE, f"ALPHA_Y{k}": BAKED_TABLE})
        t.add(ml)
        t.add(terms.visibility(k, g2, lobe.ndf, lam))
    if ms is not None:
        offset = 0                  # each lobe's pieces follow the previous lobe's
        steps = max(embed.slice_steps(term) for term in ms.lobes)   # one search function
        for k, term in enumerate(ms.lobes, start=1):
            c, tab, e_fns = embed.kulla_conty_E(k, term, offset, steps)
            offset += len(tab[0].values)
            t.consts.extend(c)
            t.tables.extend(tab)
            t.fns.extend(e_fns)
            t.tabulated.append((f"E_{k}", "Kulla-Conty's E(μ) at the lobe's α, the cubic pieces of the "
                                          "project's E(μ, α) spline (in the data texture)", term.table.error))
            scale = _channel_scales(single, ms, k - 1)
            t.consts += [Const(f"MS{k}_{ch}", s, f"Kulla-Conty scale of lobe {k}, channel {ch}: "
                               f"w F_ms/(π(1 − E_avg)), E_avg = {term.E_avg:.9g}") for ch, s in zip("RGB", scale)]
        baked.update({name: BAKED_KC for name in t.material if name != "KD"})
    fns = _library(t.fns) + t.fns + _public(len(lobes), g2.needs_phi, ms)
    uniforms = (t.material - set(baked)) if form == "uniform" else set()
    consts = [replace(c, uniform=c.name in uniforms) for c in unique_consts(t.consts)]
    info = {"uniforms": {c.name: c.value for c in consts if c.uniform},
            "baked": {k: v for k, v in sorted(baked.items())} if form == "uniform" else {},
            "tabulated": t.tabulated, "precision": precision_notes(brdf)}
    tables = _merged(t.tables)
    return Program(_header(spec, brdf, ms), consts, tables, unique_fns(fns), texture=ms is not None,
                   block=ms is None and form == "uniform" and block.fits(tables)), info


def _library(fns: list[Fn]) -> list[Fn]:
    """The helper functions (library.py) the program's formulas call."""
    used = set()
    for fn in fns:
        for expr in [fn.result, *(e for _, _, e in fn.body)]:
            used |= _library_names(expr)
    return [LIBRARY[name] for name in sorted(used)]


@functools.lru_cache(maxsize=8192)
def _library_names(expr: str) -> frozenset:
    """The library functions an expression names (the same expressions recur in every program)."""
    return frozenset(tokens(expr)) & frozenset(LIBRARY)


def _merged(tables: list[Table]) -> list[Table]:
    """Tables of one name (a lobe's part each, read through one shared helper) as one
    array, each part at its declared offset."""
    out: dict[str, Table] = {}
    for tab in tables:
        if tab.name not in out:
            if tab.offset != 0:
                raise ValueError(f"table {tab.name}: its first part starts at {tab.offset}, not 0")
            out[tab.name] = replace(tab, values=list(tab.values))
            continue
        whole = out[tab.name]
        if tab.offset != len(whole.values):
            raise ValueError(f"table {tab.name}: part at {tab.offset}, expected {len(whole.values)}")
        whole.values += list(tab.values)
    return list(out.values())


def _channel_scales(single, ms: KullaConty, i: int) -> list[float]:
    """Kulla-Conty's scale of lobe i per channel: F_ms depends on each channel's F̄."""
    per = getattr(single.fresnel, "channels", None)
    if per is None:
        return [ms.lobes[i].scale] * 3
    return [kulla_conty(replace(single, fresnel=ch)).lobes[i].scale for ch in per]


def _public(n_lobes: int, needs_phi: bool, ms) -> list[Fn]:
    fns = []
    if needs_phi:
        fns.append(Fn("azimuth_difference", "float", [("vec3", "l"), ("vec3", "v")],
                      [("float", "cr", "abs(X(l) * Y(v) - Y(l) * X(v))"), ("float", "dt", "X(l) * X(v) + Y(l) * Y(v)")],
                      "sel(cr + abs(dt) > 0.0, atan2(cr, dt), 0.0)",
                      "φ ∈ [0, π] between the tangent-plane projections of l and v; 0 where one is along n."))
    fns += [SPEC,
           Fn("D", "float", [("vec3", "m")], [],
              " + ".join(f"W{k} * D_{k}(m)" for k in range(1, n_lobes + 1)),
              "D(m) in the local frame (two lobes: their blend, itself a normalised NDF)."),
           Fn("G1", "float", [("vec3", "w")], [("float", "mu", "max(Z(w), 0.0)")],
              "sel(mu > 0.0, mu / (mu + muLambda_1(w)), 0.0)", "Smith G1 = μ/(μ + μΛ) (Heitz 2014, eq. 43), local frame."),
           Fn("G2", "float", [("vec3", "l"), ("vec3", "v")],
              [("float", "mu_l", "max(Z(l), 0.0)"), ("float", "mu_v", "max(Z(v), 0.0)"),
               ("float", "Vis", f"V_1(mu_l, mu_v, muLambda_1(l), muLambda_1(v), {_phi_expr(needs_phi)})")],
              "sel(mu_l * mu_v > 0.0, 4.0 * mu_l * mu_v * Vis, 0.0)", "G2 = 4 μ_l μ_v V, local frame.")]
    body = GEOMETRY + [("vec3", "Fr", "F(dot(v, h))")]
    if needs_phi:
        body.append(("float", "phi", "azimuth_difference(l, v)"))     # V_k below read it
    total = ["splat(fd(ml, mv, dot(l, v)))"]
    for k in range(1, n_lobes + 1):
        body += [(f"float", f"D{k}", f"D_{k}(h)"),
                 ("float", f"V{k}", f"V_{k}(ml, mv, muLambda_{k}(l), muLambda_{k}(v), {'phi' if needs_phi else '0.0'})"),
                 ("vec3", f"s{k}", f"vec3(spec(D{k}, X(Fr), V{k}, h_ok), spec(D{k}, Y(Fr), V{k}, h_ok), "
                                   f"spec(D{k}, Z(Fr), V{k}, h_ok))")]
        total.append(f"W{k} * s{k}")
    if ms is not None:
        for k in range(1, len(ms.lobes) + 1):
            body.append(("float", f"ms{k}", f"(1.0 - E_{k}(ml)) * (1.0 - E_{k}(mv))"))
            total.append(f"vec3(MS{k}_R * ms{k}, MS{k}_G * ms{k}, MS{k}_B * ms{k})")
    body.append(("vec3", "f", " + ".join(total)))
    fns.append(Fn("brdf_local", "vec3", [("vec3", "l"), ("vec3", "v")], body,
                  "sel3(and_(mu_l >= 0.0, mu_v >= 0.0), min(f, splat(F_MAX)), splat(0.0))",
                  "f(l, v) = f_d + D(h) F(v·h) G2 / (4 μ_l μ_v) [+ Kulla-Conty f_ms], RGB, no cosine;\n"
                  "l, v unit vectors in the local frame (n = +z, t = +x), pointing away from the surface;\n"
                  "0 unless both are in the closed upper hemisphere (Cook & Torrance 1982; Walter et al. 2007);\n"
                  "F_MAX where f diverges (both directions on the horizon), so f·cos θ is 0 there."))
    fns.append(world_fn())
    return fns


def _phi_expr(needs_phi: bool) -> str:
    return "azimuth_difference(l, v)" if needs_phi else "0.0"


def _header(spec: ModelSpec, brdf, ms) -> list[str]:
    return [f"BRDF Lobe Explorer {__version__}: generated code for one microfacet model.",
            f"Model: {model_query(spec)}",
            "f(l, v) = f_d(l, v) + D(h) F(v·h) G2(l, v) / (4 |n·l| |n·v|), h = (l + v)/|l + v|, no cosine",
            "(Cook & Torrance 1982; Walter et al. 2007, eq. 20; Heitz 2014)" +
            (", plus Kulla & Conty 2017's multiple-scattering lobe." if ms is not None else "."),
            "brdf(n, l, v): world space, any unit n; D, G1, G2, brdf_local: local frame n = +z, t = +x.",
            "RGB: the three channels are equal unless the Fresnel term is coloured.",
            "Each term is generated from the one formula its registry entry writes (app/physics/formula.py),",
            "the formula the server's compiled kernels run too.",
            *(f"Precision: {line}" for line in precision_notes(brdf)),
            "Regenerate it with GET /api/v1/code?lang=...&" + model_query(spec)]


def precision_notes(brdf) -> list[str]:
    """Where float32 suffices and where half precision breaks, from the model's values
    (lobes with the same note share its line)."""
    single = brdf.single() if getattr(brdf, "multiscatter", None) is not None else brdf
    notes: dict[str, list[int]] = {}
    for k, (_, lobe) in enumerate(single.lobes(), start=1):
        notes.setdefault(half_note("", lobe.ndf), []).append(k)
    return FLOAT32_NOTE + [("lobe " if len(ks) == 1 else "lobes ") + " and ".join(map(str, ks)) + note
                           for note, ks in notes.items()]


def generate(spec: ModelSpec, lang: str, form: str = "const") -> str:
    """Source text of the model in ``lang`` (glsl, hlsl or python), ``form`` const or uniform."""
    return write(program(spec, form), lang)


def describe(spec: ModelSpec, lang: str, form: str = "const") -> dict:
    """The code with what a caller needs beside it (for /code's JSON): its uniforms and
    their values for this material, what stays baked and why, every embedded table or
    approximation with its stated error, the data texture a Kulla-Conty shader reads
    (``textures``: bind each as a sampler of its name; texture.py), the precision notes
    and the line count."""
    prog, info = _assemble(spec, form)
    code = write(prog, lang)
    return {"lang": lang, "form": form, "code": code, "lines": len(code.splitlines()),
            "uniforms": info["uniforms"], "baked": info["baked"],
            "approximations": approximations(info["tabulated"], prog),
            "textures": ({texture.NAME: texture.describe(prog.tables)}
                         if prog.texture and prog.tables and lang != "python" else {}),
            "blocks": ({block.NAME: block.describe(prog.tables)}
                       if prog.block and not prog.texture and prog.tables and lang != "python" else {}),
            "precision": info["precision"]}


def approximations(tabulated, prog: Program) -> list[dict]:
    """Each place the generated code is not the float64 formula: tables and fits."""
    out = [{"what": what, "how": how, "max_error": error,
            "error_of": "G1, absolute, against the float64 Smith integral" if what.startswith("muLambda")
            else "E, absolute (the table's reported error)"} for what, how, error in tabulated]
    if any(fn.name in LIBRARY for fn in prog.functions):
        out.append({"what": "erfcx", "how": "Numerical Recipes' fit (in Beckmann's Smith Λ)",
                    "max_error": ERFCX_MAX_RELATIVE_ERROR, "error_of": "erfcx (relative)"})
    return out
