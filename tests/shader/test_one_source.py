"""One source per formula: an entry without a shader formula is a 422 naming it; the
generated code has no NaN or ∞ in the closed upper hemisphere, at grazing (one or
both directions) and at α = 1e-4, Kulla-Conty included; the kernels' scalar functions
are the formulas'."""
from __future__ import annotations

import numpy as np
import pytest

from app.errors import ParameterError
from app.model import make_spec
from app.physics.formula import Formula
from app.physics.fresnel import FRESNELS
from app.physics.fresnel.base import Fresnel
from app.physics.ndf import NDFS
from app.shader.generate import describe, generate
from tests.shader.models import registry_models


@pytest.fixture
def fresnel_without_formula():
    class Numpy(Fresnel):
        name = "numpy_only_throwaway"
        label = "numpy only (test)"
        description = "F = 1/2, numpy only"

        def F(self, c):
            return np.full(np.shape(c), 0.5)

    FRESNELS.register(Numpy)
    yield Numpy
    FRESNELS.unregister(Numpy.name)


def test_an_entry_without_a_formula_is_a_422_naming_it(fresnel_without_formula):
    with pytest.raises(ParameterError) as e:
        generate(make_spec(fresnel=fresnel_without_formula.name), "glsl")
    assert e.value.param == "fresnel" and "no shader form" in str(e.value)


def _grazing_pairs():
    """Both directions on the horizon, one of them, and normal/mirror cases; all azimuths."""
    phi = np.linspace(-np.pi, np.pi, 13)
    out = []
    for ti in (0.0, 45.0, 89.99, 90.0):
        for to in (0.0, 60.0, 90.0):
            for p in phi:
                out.append((ti, 0.0, to, np.degrees(p)))
    a = np.radians(np.array(out))
    def d(t, p):
        return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)
    return d(a[:, 0], a[:, 1]), d(a[:, 2], a[:, 3])


@pytest.mark.parametrize("ndf", list(NDFS))
@pytest.mark.parametrize("alpha", [1e-4, 0.5, 1.0])
def test_no_nan_or_inf_in_the_closed_upper_hemisphere(ndf, alpha):
    namespace: dict = {}
    for diffuse in ("lambert", "oren_nayar", "hammon"):
        params = {"ndf": ndf, "alpha": alpha, "kd": 0.5, "diffuse": diffuse}
        try:
            spec = make_spec(**params)
        except ParameterError:
            continue
        exec(compile(generate(spec, "python"), "<generated>", "exec"), namespace)
        l, v = _grazing_pairs()
        with np.errstate(all="ignore"):
            f = namespace["brdf"](np.array([0.0, 0.0, 1.0]), l, v)
        assert np.isfinite(f).all(), params
        assert (f >= 0).all(), params


@pytest.mark.parametrize("alpha", [1e-4, 1.0])
def test_no_nan_or_inf_with_kulla_conty(alpha):
    """The same with Kulla-Conty (E's pieces at α = 1e-4 and 1), every NDF that takes it,
    its longest options (tests/shader/test_full_product.py), one lobe."""
    from tests.shader.test_full_product import KULLA_CONTY_LONGEST, kulla_conty_models
    base = {k: v for k, v in KULLA_CONTY_LONGEST.items() if k not in ("alpha2", "lobe_mix")}
    models = kulla_conty_models({**base, "alpha": alpha})
    assert {m["ndf"] for m in models} == set(NDFS)
    l, v = _grazing_pairs()
    for params in models:
        namespace: dict = {}
        exec(compile(generate(make_spec(**params), "python"), "<generated>", "exec"), namespace)
        with np.errstate(all="ignore"):
            f = namespace["brdf"](np.array([0.0, 0.0, 1.0]), l, v)
        assert np.isfinite(f).all() and (f >= 0).all(), params


def test_the_kernels_scalar_functions_are_the_formulas():
    """D_scalar and mu_Lambda_scalar of each NDF that writes a formula come from it."""
    for cls in NDFS.values():
        if cls.D_formula is not None:
            assert cls.D_scalar.formula is cls.D_formula
            assert isinstance(cls.D_formula, Formula)


def test_line_counts_are_reported():
    d = describe(make_spec(ndf="ggx", alpha=0.3), "glsl", "const")
    assert d["lines"] == len(d["code"].splitlines()) and d["lines"] <= 300


def test_no_shader_of_the_registry_exceeds_300_lines():
    """Every registry model (two-lobe fits and Kulla-Conty included), GLSL and HLSL, both forms."""
    long = []
    for params in registry_models():
        spec = make_spec(**params)
        for lang in ("glsl", "hlsl"):
            for form in ("const", "uniform"):
                n = len(generate(spec, lang, form).splitlines())
                if n > 300:
                    long.append((n, lang, form, params))
    assert not long, long[:3]


@pytest.mark.parametrize("alpha", [1e-3, 3e-3, 0.01, 0.3])
def test_the_half_precision_notes_are_true(alpha):
    """The precision notes' half claims, measured in numpy float16 (IEEE half, what
    mediump may be): D's peak 1/(π α²) of GGX and q² = m_x²/α² at grazing overflow half
    exactly when the note says so; where it says nothing of overflow, half is finite."""
    notes = " ".join(describe(make_spec(ndf="ggx", alpha=alpha), "glsl")["precision"])
    with np.errstate(all="ignore"):
        a = np.float16(alpha)
        peak16 = np.float16(1.0) / (np.float16(np.pi) * a * a)
        q2_16 = np.float16(1.0) / (a * a)
    assert ("D's peak" in notes and "overflows half" in notes) == bool(np.isinf(peak16)), (notes, peak16)
    assert ("q² = m_x²/α²" in notes) == bool(np.isinf(q2_16)), (notes, q2_16)
    assert "float32 (highp) suffices" in notes
