"""The terms of the BRDF in the neutral syntax (dsl.py): D, μΛ, G2's visibility, λ(φ), F.

Each builder returns (constants, tables, functions) for one specular lobe ``k`` (1 or 2:
the second lobe of a two-lobe model has its own α). The formulas are those of
app/physics, written for float32 where that matters (said beside each); every
function works in the local frame n = +z, t = +x (direction of α_x), b = +y.
"""
from __future__ import annotations

import math

from scipy.special import gamma as gamma_fn

from .dsl import Const, Fn
from . import embed

#: Beckmann's D below this n·m: the exponent −q²/mz² ≤ −(1 − mz²)/mz² < −1e5 for α ≤ 1,
#: so D = 0 in any float format, while mz⁴ in its denominator underflows in float32
#: (0/0) below 1e-10.
BECKMANN_MZ_MIN = 1e-3
#: Walter 2007's rational fit is Λ = 0 from a = 1.6 on (docs/conventions.md §5).
WALTER_A_MAX = 1.6

def _alphas(k: int, ndf) -> list[Const]:
    return [Const(f"ALPHA_X{k}", ndf.alpha_x, f"α_x of lobe {k} (along t)"),
            Const(f"ALPHA_Y{k}", ndf.alpha_y, f"α_y of lobe {k} (along b)")]


def _q2(k: int) -> tuple[str, str, str]:
    return ("float", "q2", f"X(m) * X(m) / (ALPHA_X{k} * ALPHA_X{k}) + Y(m) * Y(m) / (ALPHA_Y{k} * ALPHA_Y{k})")


def ndf_D(k: int, ndf) -> tuple[list, list, list]:
    """D_k(m): normalised so that ∫ D (n·m) dm = 1; 0 below the horizon."""
    name = ndf.name
    consts = _alphas(k, ndf)
    body = [("float", "mz", "Z(m)"), _q2(k)]
    axy = f"ALPHA_X{k} * ALPHA_Y{k}"
    if name == "ggx":
        doc = "GGX: D = 1/(π α_x α_y (mz² + q²)²), q² = m_x²/α_x² + m_y²/α_y² (Walter et al. 2007, eq. 33; Heitz 2014, eq. 85)."
        body.append(("float", "t", "mz * mz + q2"))
        result = f"sel(mz >= 0.0, 1.0 / (PI * {axy} * t * t), 0.0)"
    elif name == "beckmann":
        doc = ("Beckmann: D = exp(−q²/mz²)/(π α_x α_y mz⁴) (Walter et al. 2007, eq. 25; Heitz 2014, eq. 83).\n"
               f"0 below n·m = BECKMANN_MZ_MIN = {BECKMANN_MZ_MIN:g}, where it is 0 in any float format.")
        consts.append(Const("BECKMANN_MZ_MIN", BECKMANN_MZ_MIN,
                            "below it exp(−q²/mz²) < exp(−1e5) while mz⁴ underflows in float32"))
        result = f"sel(mz > BECKMANN_MZ_MIN, exp(-q2 / (mz * mz)) / (PI * {axy} * mz * mz * mz * mz), 0.0)"
    elif name == "blinn_phong":
        ap = ndf.alpha_p
        doc = "Blinn-Phong: D = (α_p + 2)/(2π) (n·m)^α_p, α_p = 2/α² − 2 (Blinn 1977; Walter et al. 2007, eq. 30)."
        consts += [Const(f"ALPHA_P{k}", ap, "Phong exponent α_p = 2/α² − 2"),
                   Const(f"BP_NORM{k}", (ap + 2.0) / (2.0 * math.pi), "(α_p + 2)/(2π)")]
        # pow(0, 0) is undefined in GLSL: α_p = 0 (α = 1) is the constant lobe 1/π
        lobe = f"BP_NORM{k} * pow(max(mz, 0.0), ALPHA_P{k})" if ap > 0 else f"BP_NORM{k}"
        result = f"sel(mz >= 0.0, {lobe}, 0.0)"
    elif name == "gtr":
        g, a = ndf.gamma, ndf.alpha_x
        log_c = math.log(ndf.k / math.pi) - 2.0 * g * math.log(a)
        doc = ("GTR: D = k/(π (1 + mz²(α² − 1))^γ) = exp(ln(k/π) − 2γ ln α − γ ln(mz² + q²)), k(α, γ) of\n"
               "Burley 2012 (eq. 8, appendix B) computed once, in float64, with expm1/log1p.")
        consts += [Const(f"GAMMA{k}", g, "GTR tail exponent γ"),
                   Const(f"GTR_LOGC{k}", log_c, "ln(k(α, γ)/π) − 2γ ln α")]
        result = f"sel(mz >= 0.0, exp(GTR_LOGC{k} - GAMMA{k} * log(mz * mz + q2)), 0.0)"
    elif name == "student_t":
        g = ndf.gamma
        doc = ("Student-t: α_x α_y D = mz^(2γ−4) / (π (mz² + q²/(γ − 1))^γ), in logs (Ribardière et al. 2017).\n"
               "Its limit at the horizon mz = 0: 0 for γ > 2, 1/(π q⁴) for γ = 2, +∞ for γ < 2.")
        consts.append(Const(f"GAMMA{k}", g, "Student-t tail γ (2 = GGX)"))
        body.append(("float", "log_d", f"(2.0 * GAMMA{k} - 4.0) * log(mz) - GAMMA{k} * log(mz * mz + q2 / (GAMMA{k} - 1.0))"))
        horizon = ("0.0" if g > 2.0 else f"1.0 / (PI * {axy} * q2 * q2)" if g == 2.0 else "INF()")
        result = f"sel(mz > 0.0, exp(log_d) / (PI * {axy}), {horizon})"
    elif name == "exp_power":
        p = ndf.p
        doc = ("Exponential power: α_x α_y D = p/(π Γ(1/p)) exp(−(q²/mz²)^p) / mz⁴ (docs/conventions.md §5;\n"
               "p = 1 is Beckmann), in logs.")
        consts += [Const(f"P{k}", p, "kurtosis p (1 = Beckmann)"),
                   Const(f"EP_NORM{k}", p / (math.pi * gamma_fn(1.0 / p)), "p/(π Γ(1/p))")]
        body.append(("float", "tail", f"sel(q2 > 0.0, exp(P{k} * (log(q2) - 2.0 * log(mz))), 0.0)"))
        result = f"sel(mz > 0.0, EP_NORM{k} / ({axy}) * exp(-tail - 4.0 * log(mz)), 0.0)"
    else:
        raise ValueError(f"no code for ndf={name}")
    return consts, [], [Fn(f"D_{k}", "float", [("vec3", "m")], body, result, doc)]


# Numerical Recipes (Press et al. 2007, sec. 6.2.2, "erfc"): erfc(z) = t exp(−z² + P(t)),
# t = 1/(1 + z/2), relative error < 1.2e-7 for z ≥ 0; P without −z² is erfcx.
_ERFCX = ("t * exp(-1.26551223 + t * (1.00002368 + t * (0.37409196 + t * (0.09678418 + t * (-0.18628806"
          " + t * (0.27886807 + t * (-1.13520398 + t * (1.48851587 + t * (-0.82215223 + t * 0.17087277)))))))))")


def mu_Lambda(k: int, ndf, masking: str) -> tuple[list, list, list]:
    """muLambda_k(w) = μΛ(ω), finite everywhere (Heitz 2014, eq. 43); s = α(φ) sinθ."""
    consts, tables = [], []
    body = [("float", "mu", "max(Z(w), 0.0)"),
            ("float", "s", f"sqrt(ALPHA_X{k} * ALPHA_X{k} * X(w) * X(w) + ALPHA_Y{k} * ALPHA_Y{k} * Y(w) * Y(w))")]
    form = embed.lambda_form(ndf, masking)
    if form == "ggx":
        doc = "GGX's exact Smith Λ times μ: (√(μ² + s²) − μ)/2 = s²/(2(√(μ² + s²) + μ)) (Heitz 2014, eq. 86)."
        result = "s * s / (2.0 * (sqrt(mu * mu + s * s) + mu))"
    elif form == "beckmann":
        doc = ("Beckmann's exact Smith Λ times μ, a = μ/s: (s e^(−a²)/2)(1/√π − a erfcx(a)) (Walter et al. 2007,\n"
               "eq. 27; Heitz 2014, eq. 84); erfcx by Numerical Recipes' fit (relative error < 1.2e-7);\n"
               "the bracket loses digits for large a, where e^(−a²) makes μΛ negligible against μ.")
        if ndf.name == "blinn_phong":
            doc += "\nBlinn-Phong uses it at its Beckmann-equivalent α (Walter 2007's substitution)."
        consts.append(Const("INV_SQRT_PI", 1.0 / math.sqrt(math.pi), "1/√π"))
        body += [("float", "a", "mu / s"), ("float", "t", "1.0 / (1.0 + 0.5 * a)"),
                 ("float", "erfcx_a", _ERFCX), ("float", "bracket", "max(INV_SQRT_PI - a * erfcx_a, 0.0)")]
        result = "sel(s > 0.0, 0.5 * s * exp(-a * a) * bracket, 0.0)"
    elif form == "walter":
        doc = ("Walter 2007's rational fit of Beckmann's Λ (eq. 27, constants of docs/conventions.md §5), times μ:\n"
               "s (1 − 1.259a + 0.396a²)/(3.535 + 2.181a) for a = μ/s < 1.6, else 0; the numerator, negative\n"
               "just below 1.6, is taken as 0 there.")
        consts.append(Const("WALTER_A_MAX", WALTER_A_MAX, "Λ = 0 from here on (exact Λ < 3.4e-3 there)"))
        body.append(("float", "a", "mu / s"))
        result = ("sel(and_(s > 0.0, a < WALTER_A_MAX), s * max(1.0 - 1.259 * a + 0.396 * a * a, 0.0)"
                  " / (3.535 + 2.181 * a), 0.0)")
    elif form in ("karis", "schlick_ibl", "schlick_direct"):
        k_expr = "0.5 * alpha_phi" if form != "schlick_direct" else \
            "(sqrt(alpha_phi) + 1.0) * (sqrt(alpha_phi) + 1.0) / 8.0"
        doc = ("Schlick-GGX G1 = μ/(μ(1 − k) + k) is μΛ = k(1 − μ) (Karis 2013), k from α(φ) = s/sinθ: "
               + ("k = α/2." if form != "schlick_direct" else "k = (√α + 1)²/8 (direct light).")
               + "\nAt the pole α(φ) is undefined and multiplied by 1 − μ = 0: taken as 0.")
        body += [("float", "sin_t", "sqrt(X(w) * X(w) + Y(w) * Y(w))"),
                 ("float", "alpha_phi", "sel(sin_t > 0.0, s / sin_t, 0.0)")]
        result = f"{k_expr} * (1.0 - mu)"
    else:   # a table of h(a) = μΛ/s in ln a, cubic Hermite (embed.py)
        c, t, doc, fn_body, result = embed.lambda_table(k, ndf, form)
        consts += c
        tables += t
        body += fn_body
    return consts, tables, [Fn(f"muLambda_{k}", "float", [("vec3", "w")], body, result, doc)]


def visibility(k: int, g2, ndf) -> tuple[list, list, list]:
    """V_k = G2/(4 μ_l μ_v) from μ ≥ 0 and μΛ of both directions; +∞ where it diverges."""
    params = [("float", "mu_l"), ("float", "mu_v"), ("float", "ml_l"), ("float", "ml_v"), ("float", "phi")]
    consts = []
    body = [("float", "a_l", "mu_l + ml_l"), ("float", "a_v", "mu_v + ml_v")]
    name = g2.name
    if name == "separable":
        doc = "Separable G2 = G1(l) G1(v) (Heitz 2014, eq. 98): V = 1/(4 a_l a_v), a = μ + μΛ."
        result = "sel(a_l * a_v > 0.0, 0.25 / (a_l * a_v), INF())"
    elif name == "height_correlated":
        doc = "Height-correlated G2 = 1/(1 + Λ_l + Λ_v) (Heitz 2014, eq. 99): V = 1/(4(μ_l μ_v + μ_v μΛ_l + μ_l μΛ_v))."
        body.append(("float", "den", "mu_l * mu_v + mu_v * ml_l + mu_l * ml_v"))
        result = "sel(den > 0.0, 0.25 / den, INF())"
    elif name == "direction_correlated":
        doc = ("Direction-correlated G2 = λ G1(l)G1(v) + (1 − λ) min(G1(l), G1(v)) (Ashikhmin et al. 2000;\n"
               "Heitz 2014, sec. 6): V = λ/(4 a_l a_v) + (1 − λ)/(4 max(μ_v a_l, μ_l a_v)).")
        body += [("float", "lam", "lambda_phi(phi)"), ("float", "big", "max(mu_v * a_l, mu_l * a_v)")]
        result = "sel(big > 0.0, 0.25 * (lam / (a_l * a_v) + (1.0 - lam) / big), INF())"
    elif name == "height_direction_correlated":
        doc = ("Height-direction-correlated G2 = 1/(1 + max(Λl, Λv) + λ min(Λl, Λv)) (Heitz 2014, sec. 6),\n"
               "times μ_l μ_v over itself.")
        body += [("float", "lam", "lambda_phi(phi)"), ("float", "A", "mu_v * ml_l"), ("float", "B", "mu_l * ml_v"),
                 ("float", "den", "mu_l * mu_v + max(A, B) + lam * min(A, B)")]
        result = "sel(den > 0.0, 0.25 / den, INF())"
    elif name == "hammon":
        doc = "Hammon 2017 (GDC): V ≈ 0.5 / lerp(2 μ_l μ_v, μ_l + μ_v, α), isotropic GGX; an approximation."
        body.append(("float", "den", f"(1.0 - ALPHA_X{k}) * 2.0 * mu_l * mu_v + ALPHA_X{k} * (mu_l + mu_v)"))
        result = "sel(den > 0.0, 0.5 / den, INF())"
    else:
        raise ValueError(f"no code for g2={name}")
    return consts, [], [Fn(f"V_{k}", "float", params, body, result, doc)]


def lambda_phi(name: str) -> Fn:
    """λ(φ) of the direction-correlated forms, φ ∈ [0, π] the azimuth difference."""
    if name == "ashikhmin":
        return Fn("lambda_phi", "float", [("float", "phi")], [],
                  "1.0 - exp(-7.3 * phi * phi)", "λ(φ) = 1 − exp(−7.3 φ²) (Ashikhmin, Premože, Shirley 2000).")
    if name == "van_ginneken":
        return Fn("lambda_phi", "float", [("float", "phi")], [("float", "x", "4.41 * phi")],
                  "x / (x + 1.0)", "λ(φ) = 4.41φ/(4.41φ + 1) (van Ginneken, Stavridi, Koenderink 1998).")
    raise ValueError(f"no code for lambda_phi={name}")


def fresnel(channels: list[dict], name: str) -> tuple[list, list, list]:
    """F(cos θ_d) per RGB channel; ``channels`` holds each channel's parameters."""
    consts, fns = [], []
    rgb = "RGB"
    body = [("float", "c", "clamp(cos_theta_d, 0.0, 1.0)")]
    if name == "none":
        return [], [], [Fn("F", "vec3", [("float", "cos_theta_d")], [], "splat(1.0)", "F = 1.")]
    if name == "schlick":
        p = channels[0]["fresnel_p"]
        consts.append(Const("FRESNEL_P", p, "Schlick exponent p (5 in Schlick 1994)"))
        for ch, values in zip(rgb, channels):
            consts += [Const(f"F0_{ch}", values["f0"], f"F₀, channel {ch}"),
                       Const(f"F90_{ch}", values["f90"], f"F₉₀, channel {ch}")]
        body.append(("float", "w", "pow(1.0 - c, FRESNEL_P)"))
        parts = [f"F0_{ch} + (F90_{ch} - F0_{ch}) * w" for ch in rgb]
        doc = "Schlick 1994, eq. 15, generalised: F = F₀ + (F₉₀ − F₀)(1 − cos θ_d)^p."
    elif name == "dielectric":
        for ch, values in zip(rgb, channels):
            consts.append(Const(f"ETA_{ch}", values["ior"], f"index η, channel {ch}"))
        fns.append(_dielectric_fn())
        parts = [f"F_dielectric(c, ETA_{ch})" for ch in rgb]
        doc = "Exact unpolarised Fresnel reflectance of a dielectric of index η seen from air, per channel."
    elif name == "conductor":
        for ch, values in zip(rgb, channels):
            consts += [Const(f"ETA_{ch}", values["ior"], f"real part η of the index, channel {ch}"),
                       Const(f"KAPPA_{ch}", values["k"], f"extinction κ, channel {ch}")]
        fns.append(_conductor_fn())
        parts = [f"F_conductor(c, ETA_{ch}, KAPPA_{ch})" for ch in rgb]
        doc = "Exact unpolarised Fresnel reflectance of a conductor of index η + iκ seen from air, per channel."
    else:
        raise ValueError(f"no code for fresnel={name}")
    fns.append(Fn("F", "vec3", [("float", "cos_theta_d")], body, f"vec3({', '.join(parts)})", doc))
    return consts, [], fns


def _dielectric_fn() -> Fn:
    body = [("float", "e2", "eta * eta"), ("float", "d", "(eta - 1.0) * (eta + 1.0)"),
            ("float", "g", "sqrt(d + c * c)"), ("float", "den_s", "d + 2.0 * c * (c + g)"),
            ("float", "den_p", "d + c * c + e2 * c * (e2 * c + 2.0 * g)"),
            ("float", "rs", "-d / den_s"), ("float", "rp", "d * ((e2 + 1.0) * c * c - 1.0) / den_p")]
    doc = ("(r_s² + r_p²)/2 with r_s = −d/(d + 2c(c + g)), r_p = d((η² + 1)c² − 1)/(d + c² + η²c(η²c + 2g)),\n"
           "d = η² − 1, g = √(d + c²) (Born & Wolf sec. 1.5.2, expanded so nothing cancels as η → 1).")
    return Fn("F_dielectric", "float", [("float", "c"), ("float", "eta")], body,
              "sel(and_(den_s > 0.0, den_p > 0.0), 0.5 * (rs * rs + rp * rp), 0.0)", doc)


def _conductor_fn() -> Fn:
    body = [("float", "c2", "c * c"), ("float", "s2", "max(1.0 - c2, 0.0)"),
            ("float", "t0", "eta * eta - kappa * kappa - s2"), ("float", "ek2", "eta * kappa * eta * kappa"),
            ("float", "A", "sqrt(t0 * t0 + 4.0 * ek2)"),
            ("float", "a2", "sel(t0 >= 0.0, 0.5 * (A + t0), sel(A - t0 > 0.0, 2.0 * ek2 / (A - t0), 0.0))"),
            ("float", "b2", "sel(t0 >= 0.0, sel(A + t0 > 0.0, 2.0 * ek2 / (A + t0), 0.0), 0.5 * (A - t0))"),
            ("float", "a", "sqrt(a2)"),
            ("float", "Rs", "((a - c) * (a - c) + b2) / ((a + c) * (a + c) + b2)"),
            ("float", "u", "A * c2 + s2 * s2"), ("float", "q", "2.0 * a * c * s2"),
            ("float", "Rp", "Rs * (u - q) / (u + q)")]
    doc = ("Born & Wolf sec. 14.2 in real arithmetic (pbrt-v4's FrComplex): a + ib = √((η + iκ)² − sin²θ),\n"
           "A = a² + b²; a² (or b²) as 2η²κ²/(A ∓ t₀) where A ± t₀ would cancel. κ ≫ η and η = 0 work.")
    return Fn("F_conductor", "float", [("float", "c"), ("float", "eta"), ("float", "kappa")], body,
              "0.5 * (Rs + Rp)", doc)
