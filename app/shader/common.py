"""What every generated program shares, whatever the model family: the guards of the
half vector and the tangent frame, the finite stand-in for a divergent f, the world-space
entry point ``brdf(n, l, v)`` and the half-precision notes."""
from __future__ import annotations

import numpy as np

from .dsl import Const, Fn

#: |l + v| below which h is undefined and the specular term is 0: l and v opposite to
#: within 1e-6 rad, the resolution of a float32 unit vector after a few roundings.
HALF_VECTOR_MIN_NORM = 1e-6
#: |x − n(n·x)| below which the tangent frame projects y instead of x: n within 0.06°
#: of ±x (no fixed axis gives a continuous frame over the whole sphere).
FRAME_MIN = 1e-3
#: f returned where it truly diverges (both directions on the horizon, where /eval says
#: +∞): a finite stand-in, so that f·cos θ = 0 there and no ∞ reaches a frame buffer;
#: 1e30 leaves float32 headroom (3.4e38) for the sum of the lobes and the diffuse term.
F_MAX = 1e30
#: float16 (half; GLSL mediump may be it): largest finite value and relative precision.
HALF_MAX, HALF_EPS = 65504.0, 2.0 ** -11


#: The float32 statement every program's precision notes start with.
FLOAT32_NOTE = ["float32 (highp) suffices: every term is checked against the float64 reference to 1e-5 relative",
                "in WebGL2 (tests/e2e/test_shader_webgl.py) on directions up to 88° from the normal."]


def guard_consts() -> list[Const]:
    return [Const("PI", np.pi, "π"),
            Const("HALF_VECTOR_MIN_NORM", HALF_VECTOR_MIN_NORM,
                  "|l + v| below which h is undefined (l = −v to float32 resolution): no specular"),
            Const("FRAME_MIN", FRAME_MIN, "n this close to ±x: the frame projects y instead of x"),
            Const("F_MAX", F_MAX, "f where it diverges (both directions on the horizon): finite, so f·cos θ = 0 there")]


#: The local-frame geometry every brdf_local starts with: μ's, h (guarded) and its existence.
GEOMETRY = [("float", "mu_l", "Z(l)"), ("float", "mu_v", "Z(v)"),
            ("float", "ml", "max(mu_l, 0.0)"), ("float", "mv", "max(mu_v, 0.0)"),
            ("vec3", "hs", "l + v"), ("float", "hn", "length(hs)"),
            ("bool", "h_ok", "hn > HALF_VECTOR_MIN_NORM"),
            ("vec3", "h", "vec3(X(hs) / max(hn, HALF_VECTOR_MIN_NORM), Y(hs) / max(hn, HALF_VECTOR_MIN_NORM), "
                          "Z(hs) / max(hn, HALF_VECTOR_MIN_NORM))")]

SPEC = Fn("spec", "float", [("float", "D"), ("float", "F"), ("float", "V"), ("bool", "ok")], [],
          "sel(and_(ok, D * F > 0.0), D * F * V, 0.0)",
          "D F V where h exists and D F > 0 (so that 0 × ∞ never happens), else 0.")


def world_fn() -> Fn:
    """brdf(n, l, v): the project's tangent frame around n, then brdf_local."""
    frame = [("vec3", "nn", "normalize(n)"),
             ("vec3", "tx", "vec3(1.0 - X(nn) * X(nn), -Y(nn) * X(nn), -Z(nn) * X(nn))"),
             ("vec3", "ty", "vec3(-X(nn) * Y(nn), 1.0 - Y(nn) * Y(nn), -Z(nn) * Y(nn))"),
             ("vec3", "t", "normalize(sel3(length(tx) > FRAME_MIN, tx, ty))"),
             ("vec3", "b", "cross(nn, t)")]
    return Fn("brdf", "vec3", [("vec3", "n"), ("vec3", "l"), ("vec3", "v")], frame,
              "brdf_local(vec3(dot(l, t), dot(l, b), dot(l, nn)), vec3(dot(v, t), dot(v, b), dot(v, nn)))",
              "f for a surface of normal n (world space; l, v unit, away from the surface). Tangent frame:\n"
              "t = x − n(n·x) normalised (y instead when n is within 0.06° of ±x), b = n × t; α_x is along t.")


def half_note(label: str, ndf) -> str:
    """Where half precision breaks for one lobe: D's peak at the normal and
    q² = m_x²/α² at grazing against half's range."""
    peak = float(ndf.D(np.array([0.0, 0.0, 1.0])))
    a_min = min(ndf.alpha_x, ndf.alpha_y)
    half = []
    if peak > HALF_MAX:
        half.append(f"D's peak {peak:.3g} overflows half (max {HALF_MAX:g})")
    if 1.0 / a_min ** 2 > HALF_MAX:
        half.append(f"q² = m_x²/α² reaches {1.0 / a_min ** 2:.3g} at grazing and overflows half")
    half.append(f"half's relative precision {HALF_EPS:.1e} bounds f's to about 1e-3 at best")
    return f"{label} in half/mediump: " + "; ".join(half) + "."


def unique_fns(fns: list[Fn]) -> list[Fn]:
    """The first function of each name, in order (a part's helpers arrive once per use)."""
    seen, out = set(), []
    for fn in fns:
        if fn.name not in seen:
            seen.add(fn.name)
            out.append(fn)
    return out


def unique_consts(consts: list[Const]) -> list[Const]:
    """The first constant of each name, in order; one name with two values is an error."""
    seen, out = {}, []
    for c in consts:
        if c.name in seen:
            if seen[c.name] != c.value:
                raise ValueError(f"constant {c.name} given two values: {seen[c.name]!r}, {c.value!r}")
            continue
        seen[c.name] = c.value
        out.append(c)
    return out
