"""The configured model as one self-contained program: GLSL, HLSL or Python (numpy).

``brdf(n, l, v)`` returns f (RGB, no cosine) with l and v pointing away from the surface;
it builds the project's tangent frame (t = +x projected onto the tangent plane, b = n × t)
and calls ``brdf_local``. ``D``, ``G1``, ``G2`` and ``F`` are the helpers, in the local
frame n = +z. The terms are those of app/physics (terms.py, embed.py).
"""
from __future__ import annotations

import math
from dataclasses import replace

from .. import __version__
from ..errors import ParameterError
from ..integrate.compensation import KullaConty, kulla_conty
from ..model import ModelSpec
from . import embed, terms
from .dsl import Const, Fn, Program
from .emit import write

#: |l + v| below which h is undefined and the specular term is 0: l and v opposite to
#: within 1e-6 rad, the resolution of a float32 unit vector after a few roundings.
HALF_VECTOR_MIN_NORM = 1e-6
#: |x − n(n·x)| below which the tangent frame projects y instead of x: n within 0.06°
#: of ±x (no fixed axis gives a continuous frame over the whole sphere).
FRAME_MIN = 1e-3


def model_query(spec: ModelSpec) -> str:
    """The query string that reproduces the model (derived values left out)."""
    derived = set(getattr(spec.brdf().ndf, "derived_doc", {}) or {})
    if spec.values.get("material"):
        derived.add("fresnel")               # set by the material
    return "&".join(f"{k}={v:g}" if isinstance(v, float) else f"{k}={v}"
                    for k, v in spec.values.items() if v is not None and k not in derived)


def fresnel_channels(fresnel) -> tuple[str, list[dict]]:
    """The registry name of each channel's Fresnel and each channel's parameters (equal
    channels for a scalar Fresnel; a material's three exact ones otherwise)."""
    per = getattr(fresnel, "channels", None) or [fresnel] * 3
    return per[0].name, [{p.name: getattr(ch, p.name) for p in ch.params} for ch in per]


def program(spec: ModelSpec) -> Program:
    if spec.values.get("model", "microfacet") != "microfacet":
        raise ParameterError("model", f"code generation writes model=microfacet only; got "
                                      f"model={spec.values['model']}")
    diffuse = spec.values.get("diffuse", "lambert")
    if diffuse != "lambert":
        raise ParameterError("diffuse", f"code generation writes the diffuse term as Lambert's kd/π only; "
                                        f"got diffuse={diffuse}")
    brdf = spec.brdf()
    ms: KullaConty | None = getattr(brdf, "multiscatter", None)
    single = brdf.single() if ms is not None else brdf
    lobes = single.lobes()
    g2 = single.g2
    consts = [Const("PI", math.pi, "π"),
              Const("KD", brdf.kd, "weight of the Lambertian term kd/π"),
              Const("HALF_VECTOR_MIN_NORM", HALF_VECTOR_MIN_NORM,
                    "|l + v| below which h is undefined (l = −v to float32 resolution): no specular"),
              Const("FRAME_MIN", FRAME_MIN, "n this close to ±x: the frame projects y instead of x")]
    tables, fns = [], []

    def add(parts):
        c, t, f = parts
        consts.extend(c)
        tables.extend(t)
        fns.extend(f)

    name, channels = fresnel_channels(brdf.fresnel)
    add(terms.fresnel(channels, name))
    if g2.needs_phi:
        fns.append(terms.lambda_phi(_lambda_phi_name(single)))
    for k, (weight, lobe) in enumerate(lobes, start=1):
        consts.append(Const(f"W{k}", weight, f"weight of specular lobe {k}"))
        add(terms.ndf_D(k, lobe.ndf))
        add(terms.mu_Lambda(k, lobe.ndf, lobe.masking.name))
        add(terms.visibility(k, g2, lobe.ndf))
    if ms is not None:
        for k, term in enumerate(ms.lobes, start=1):
            c, t, f = embed.kulla_conty_E(k, term)
            consts.extend(c)
            tables.extend(t)
            fns.append(f)
            scale = _channel_scales(single, ms, k - 1)
            consts += [Const(f"MS{k}_{ch}", s, f"Kulla-Conty scale of lobe {k}, channel {ch}: "
                             "w F_ms/(π(1 − E_avg))") for ch, s in zip("RGB", scale)]
            consts.append(Const(f"E_AVG_{k}", term.E_avg, f"E_avg of lobe {k} (F = 1), of the table itself"))
    fns += _public(len(lobes), g2.needs_phi, ms)
    return Program(_header(spec, brdf, ms), _unique(consts), tables, fns)


def _lambda_phi_name(brdf) -> str:
    from ..physics.g2 import DEFAULT_LAMBDA_PHI, LAMBDA_PHIS
    for name, entry in LAMBDA_PHIS.items():
        if entry.fn is brdf.lambda_phi:
            return name
    return DEFAULT_LAMBDA_PHI


def _channel_scales(single, ms: KullaConty, i: int) -> list[float]:
    """Kulla-Conty's scale of lobe i per channel: F_ms depends on each channel's F̄."""
    per = getattr(single.fresnel, "channels", None)
    if per is None:
        return [ms.lobes[i].scale] * 3
    return [kulla_conty(replace(single, fresnel=ch)).lobes[i].scale for ch in per]


def _unique(consts: list[Const]) -> list[Const]:
    seen, out = set(), []
    for c in consts:
        if c.name not in seen:
            seen.add(c.name)
            out.append(c)
    return out


def _public(n_lobes: int, needs_phi: bool, ms) -> list[Fn]:
    fns = []
    if needs_phi:
        fns.append(Fn("azimuth_difference", "float", [("vec3", "l"), ("vec3", "v")],
                      [("float", "cr", "abs(X(l) * Y(v) - Y(l) * X(v))"), ("float", "dt", "X(l) * X(v) + Y(l) * Y(v)")],
                      "sel(cr + abs(dt) > 0.0, atan2(cr, dt), 0.0)",
                      "φ ∈ [0, π] between the tangent-plane projections of l and v; 0 where one is along n."))
    fns += [Fn("spec", "float", [("float", "D"), ("float", "F"), ("float", "V"), ("bool", "ok")], [],
              "sel(and_(ok, D * F > 0.0), D * F * V, 0.0)",
              "D F V where h exists and D F > 0 (so that 0 × ∞ never happens), else 0."),
           Fn("D", "float", [("vec3", "m")], [],
              " + ".join(f"W{k} * D_{k}(m)" for k in range(1, n_lobes + 1)),
              "D(m) in the local frame (two lobes: their blend, itself a normalised NDF)."),
           Fn("G1", "float", [("vec3", "w")], [("float", "mu", "max(Z(w), 0.0)")],
              "sel(mu > 0.0, mu / (mu + muLambda_1(w)), 0.0)", "Smith G1 = μ/(μ + μΛ) (Heitz 2014, eq. 43), local frame."),
           Fn("G2", "float", [("vec3", "l"), ("vec3", "v")],
              [("float", "mu_l", "max(Z(l), 0.0)"), ("float", "mu_v", "max(Z(v), 0.0)"),
               ("float", "Vis", f"V_1(mu_l, mu_v, muLambda_1(l), muLambda_1(v), {_phi_expr(needs_phi)})")],
              "sel(mu_l * mu_v > 0.0, 4.0 * mu_l * mu_v * Vis, 0.0)", "G2 = 4 μ_l μ_v V, local frame.")]
    body = [("float", "mu_l", "Z(l)"), ("float", "mu_v", "Z(v)"),
            ("float", "ml", "max(mu_l, 0.0)"), ("float", "mv", "max(mu_v, 0.0)"),
            ("vec3", "hs", "l + v"), ("float", "hn", "length(hs)"),
            ("bool", "h_ok", "hn > HALF_VECTOR_MIN_NORM"),
            ("vec3", "h", "vec3(X(hs) / max(hn, HALF_VECTOR_MIN_NORM), Y(hs) / max(hn, HALF_VECTOR_MIN_NORM), "
                          "Z(hs) / max(hn, HALF_VECTOR_MIN_NORM))"),
            ("vec3", "Fr", "F(dot(v, h))")]
    if needs_phi:
        body.append(("float", "phi", "azimuth_difference(l, v)"))
    total = ["splat(KD / PI)"]
    for k in range(1, n_lobes + 1):
        body += [(f"float", f"D{k}", f"D_{k}(h)"),
                 ("float", f"V{k}", f"V_{k}(ml, mv, muLambda_{k}(l), muLambda_{k}(v), {_phi_expr(needs_phi)})"),
                 ("vec3", f"s{k}", f"vec3(spec(D{k}, X(Fr), V{k}, h_ok), spec(D{k}, Y(Fr), V{k}, h_ok), "
                                   f"spec(D{k}, Z(Fr), V{k}, h_ok))")]
        total.append(f"W{k} * s{k}")
    if ms is not None:
        for k in range(1, len(ms.lobes) + 1):
            body.append(("float", f"ms{k}", f"(1.0 - E_{k}(ml)) * (1.0 - E_{k}(mv))"))
            total.append(f"vec3(MS{k}_R * ms{k}, MS{k}_G * ms{k}, MS{k}_B * ms{k})")
    body.append(("vec3", "f", " + ".join(total)))
    fns.append(Fn("brdf_local", "vec3", [("vec3", "l"), ("vec3", "v")], body,
                  "sel3(and_(mu_l >= 0.0, mu_v >= 0.0), f, splat(0.0))",
                  "f(l, v) = kd/π + D(h) F(v·h) G2 / (4 μ_l μ_v) [+ Kulla-Conty f_ms], RGB, no cosine;\n"
                  "l, v unit vectors in the local frame (n = +z, t = +x), pointing away from the surface;\n"
                  "0 unless both are in the closed upper hemisphere (Cook & Torrance 1982; Walter et al. 2007)."))
    frame = [("vec3", "nn", "normalize(n)"),
             ("vec3", "tx", "vec3(1.0 - X(nn) * X(nn), -Y(nn) * X(nn), -Z(nn) * X(nn))"),
             ("vec3", "ty", "vec3(-X(nn) * Y(nn), 1.0 - Y(nn) * Y(nn), -Z(nn) * Y(nn))"),
             ("vec3", "t", "normalize(sel3(length(tx) > FRAME_MIN, tx, ty))"),
             ("vec3", "b", "cross(nn, t)")]
    fns.append(Fn("brdf", "vec3", [("vec3", "n"), ("vec3", "l"), ("vec3", "v")], frame,
                  "brdf_local(vec3(dot(l, t), dot(l, b), dot(l, nn)), vec3(dot(v, t), dot(v, b), dot(v, nn)))",
                  "f for a surface of normal n (world space; l, v unit, away from the surface). Tangent frame:\n"
                  "t = x − n(n·x) normalised (y instead when n is within 0.06° of ±x), b = n × t; α_x is along t."))
    return fns


def _phi_expr(needs_phi: bool) -> str:
    return "azimuth_difference(l, v)" if needs_phi else "0.0"


def _header(spec: ModelSpec, brdf, ms) -> list[str]:
    return [f"BRDF Lobe Explorer {__version__}: generated code for one microfacet model.",
            f"Model: {model_query(spec)}",
            "f(l, v) = kd/π + D(h) F(v·h) G2(l, v) / (4 |n·l| |n·v|), h = (l + v)/|l + v|, no cosine",
            "(Cook & Torrance 1982; Walter et al. 2007, eq. 20; Heitz 2014)" +
            (", plus Kulla & Conty 2017's multiple-scattering lobe." if ms is not None else "."),
            "brdf(n, l, v): world space, any unit n; D, G1, G2, brdf_local: local frame n = +z, t = +x.",
            "RGB: the three channels are equal unless the Fresnel term is coloured.",
            "Regenerate it with GET /api/v1/code?lang=...&" + model_query(spec)]


def generate(spec: ModelSpec, lang: str) -> str:
    """Source text of the model in ``lang`` (glsl, hlsl or python)."""
    return write(program(spec), lang)
