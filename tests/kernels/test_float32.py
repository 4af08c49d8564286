"""The float32 f loop (app/kernels/float32.py): generated from the same formulas as the
float64 loops, float32 in its compiled code, within its stated error against the float64
numpy path (the reference, never the float32 output), and refused where it has no float32
form or its error is not bounded.

Each float32 model class costs a compile (~1.5-4 s): two classes here, chosen to cover the
most float32-sensitive formulas (the page's default is the bench's model, GGX + smith +
separable + F = 1; the other has the Schlick-direct masking's square roots, the dielectric
Fresnel near total internal reflection and EON's arccos). REL_ERROR_K was measured over
all five GGX classes (FLOAT32_CASES) with app.kernels.float32.measure.
"""
from __future__ import annotations

import numba
import numpy as np
import pytest

from app import kernels
from app.kernels import compose
from app.kernels import float32 as k32
from app.model import make_spec
from app.physics.formula import float32_literal
from app.physics.ndf.ggx import GGX

pytestmark = pytest.mark.skipif(not kernels.ENABLED, reason="numba absent or BRDF_FAST=0")

#: every GGX float32 class the bound was measured on (make_spec's names)
FLOAT32_CASES = [
    dict(ndf="ggx", masking="smith", g2="separable", fresnel="none"),
    dict(ndf="ggx", masking="smith", g2="height_correlated", fresnel="schlick"),
    dict(ndf="ggx", masking="karis", g2="hammon", fresnel="schlick", diffuse="oren_nayar"),
    dict(ndf="ggx", masking="schlick_direct", g2="separable", fresnel="dielectric", diffuse="eon"),
    dict(ndf="ggx", masking="schlick_ibl", g2="direction_correlated", lambda_phi="ashikhmin",
         fresnel="none", diffuse="hammon"),
]
TESTED = [FLOAT32_CASES[0], FLOAT32_CASES[3]]


@pytest.mark.parametrize("case", TESTED, ids=lambda c: "-".join(c.values()))
@pytest.mark.parametrize("alpha", [1.0, 0.1, 1e-2, 1e-4])
def test_error_within_the_stated_bound(case, alpha):
    brdf = make_spec(**case, alpha=alpha, alpha_y=max(alpha / 2, 1e-4), kd=0.3).brdf()
    m = k32.measure(brdf, n=40_000, seed=7)
    assert m["inf_agree"] and m["zero_agree"], m
    assert m["k"] <= k32.REL_ERROR_K, m
    assert m["rel"] > 0.0     # it is float32: not the float64 loop by mistake


def test_the_loop_is_float32():
    """The compiled loop of the bench's model, recompiled uncached to read its LLVM IR:
    8-lane float vectors, no double anywhere in the loop (a float64 literal or a math
    function promoting would show as fpext/double)."""
    brdf = make_spec(**FLOAT32_CASES[0]).brdf()
    module = compose.load32(k32.components(brdf))
    loop = numba.njit(nogil=True, error_model="numpy")(module.f_loop.py_func)
    k = k32.Kernel32(None, module)
    k._f_loop = loop
    k.warm()
    (sig,) = loop.signatures
    ir = loop.inspect_llvm(sig)
    # the compiled function itself, not numba's wrapper that unboxes Python floats
    body = "\n".join(block for block in ir.split("\ndefine ")[1:] if "f_loop" in (head := block.split("\n")[0])
                     and "cpython" not in head and "cfunc" not in head)
    assert "<8 x float>" in body
    assert "double" not in body, [line for line in body.splitlines() if "double" in line][:5]


def test_float64_stays_the_default():
    brdf = make_spec(**FLOAT32_CASES[0]).brdf()
    assert kernels.f(brdf, [[0.0, 0.6, 0.8]], [[0.0, -0.6, 0.8]]).dtype == np.float64
    assert k32.f(brdf, [[0.0, 0.6, 0.8]], [[0.0, -0.6, 0.8]]).dtype == np.float32


@pytest.mark.parametrize("given, needle", [
    (dict(ndf="beckmann"), "exp"),
    (dict(ndf="blinn_phong"), "exponent"),
    (dict(ndf="ggx", masking="smith_numeric"), "masking=smith_numeric"),
    (dict(ndf="gtr"), "Smith μΛ"),
    (dict(ndf="student_t"), "Smith μΛ"),
])
def test_unsupported_models_say_why(given, needle):
    why = k32.unsupported(make_spec(**given).brdf())
    assert why is not None and needle in why, why
    with pytest.raises(k32.Float32Unsupported):
        k32.f(make_spec(**given).brdf(), [[0.0, 0.0, 1.0]], [[0.0, 0.0, 1.0]])


def test_translation_types_every_number():
    text = GGX.D_formula.scalar32_source("d")
    assert "f32(1.0)" in text and "PI = f32(" in text
    # the pair's code: float literals wrapped, indices and comments left alone
    assert compose.float32_code("x = 1.0 / y[3 * k]  # 0.5") == "x = f32(1.0) / y[3 * k]  # 0.5"
    with pytest.raises(ValueError, match="float32"):
        float32_literal(1e-50)
    with pytest.raises(ValueError, match="float32"):
        float32_literal(1e39)
