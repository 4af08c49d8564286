"""The registries' capabilities: exact / approximates, schlick_basis, simplifies_to,
sample_visible, and the one registration idiom. Each claim is checked numerically
against the models' own formulas, not against the attribute that makes it."""
from __future__ import annotations

from dataclasses import replace

import numpy as np
import pytest

from app.physics.fresnel import FRESNELS
from app.physics.g2 import G2_FORMS
from app.physics.masking import G1, MASKINGS
from app.physics.ndf import NDFS
from app.physics.vectors import direction_deg

REGISTRIES = {"ndf": NDFS, "masking": MASKINGS, "g2": G2_FORMS, "fresnel": FRESNELS}
RNG = np.random.default_rng(5)


@pytest.mark.parametrize("kind", REGISTRIES)
def test_one_idiom_refuses_a_name_twice(kind):
    registry = REGISTRIES[kind]
    entry = next(iter(registry.values()))
    with pytest.raises(ValueError, match="registered twice"):
        registry.register(entry)


def test_masking_exact():
    ggx, beckmann, blinn = NDFS["ggx"](0.3), NDFS["beckmann"](0.3), NDFS["blinn_phong"](0.3)
    assert MASKINGS["smith"].exact(ggx) is MASKINGS["smith"]
    assert MASKINGS["walter"].exact(beckmann) is MASKINGS["smith"]
    assert MASKINGS["karis"].exact(ggx) is MASKINGS["smith"]
    # Blinn-Phong's "smith" is Walter's Beckmann substitution: the exact one is the integral
    assert MASKINGS["smith"].exact(blinn) is MASKINGS["smith_numeric"]
    assert MASKINGS["walter"].exact(blinn) is MASKINGS["smith_numeric"]
    for m in MASKINGS.values():
        assert (m.approximates is None) == (m.exact(ggx) is m or m.uses_ndf_Lambda)


def test_g2_and_fresnel_exact():
    assert G2_FORMS["hammon"].exact() is G2_FORMS["height_correlated"]
    assert G2_FORMS["hammon"].approximation and not G2_FORMS["separable"].approximation
    schlick = FRESNELS["schlick"](f0=0.2)
    exact = schlick.exact()
    assert exact.name == schlick.approximates == "dielectric"
    # the same F₀: both agree at normal incidence
    assert exact.F(1.0) == pytest.approx(schlick.F(1.0), rel=1e-12)
    assert FRESNELS["conductor"]().exact().name == "conductor"


#: the Fresnel models with no Schlick basis: the exact ones (a table over their own
#: parameters instead); every other one must state its basis
EXACT_FRESNELS = {"dielectric", "conductor"}


@pytest.mark.parametrize("name", FRESNELS)
def test_schlick_basis_reconstructs_F(name):
    """Where a model says it is Σ c S_p, that sum is its F (S_None = 1, S_p = (1 − c)^p);
    exactly the exact models say they are not."""
    cls = FRESNELS[name]
    values = {p.name: RNG.uniform(p.lo, p.hi) for p in cls.params}
    fr = cls(**values)
    basis = fr.schlick_basis()
    assert (basis is None) == (name in EXACT_FRESNELS), (name, basis)
    if basis is None:
        return
    c = np.linspace(0.0, 1.0, 101)
    total = sum(w * (np.ones_like(c) if p is None else (1.0 - c) ** p) for w, p in basis)
    np.testing.assert_allclose(total, fr.F(c), rtol=1e-13, atol=1e-15)


def test_exact_fresnels_are_not_on_the_schlick_basis():
    """The dielectric is not F₀ + (1 − F₀)(1 − c)^5: it must not claim a basis."""
    d = FRESNELS["dielectric"](ior=1.5)
    c = np.linspace(0.0, 1.0, 11)
    f0 = d.F(1.0)
    assert np.max(np.abs(d.F(c) - (f0 + (1 - f0) * (1 - c) ** 5))) > 1e-3
    assert d.schlick_basis() is None


def _pairs(ndf_cls):
    rng = np.random.default_rng(7)
    theta = rng.uniform(0, 89.9, 64)
    return direction_deg(theta, rng.uniform(0, 360, 64) if ndf_cls.anisotropic else 0.0)


@pytest.mark.parametrize("name", [n for n, c in NDFS.items() if c.simplifies_to])
def test_ndf_simplifies_to(name):
    cls = NDFS[name]
    for values, other in cls.simplifies_to:
        for alpha in (0.05, 0.3, 1.0):
            a, b = cls(alpha, **values), NDFS[other](alpha)
            m = _pairs(cls)
            # D in logs (exp_power) against the direct form: ~|exponent| ulps apart
            np.testing.assert_allclose(a.D(m), b.D(m), rtol=1e-10, atol=1e-300)
            # a tabulated Λ (GTR) against the closed form: the table's own bound
            np.testing.assert_allclose(G1(m[:, 2], a.mu_Lambda(m)), G1(m[:, 2], b.mu_Lambda(m)),
                                       atol=1e-8)


def test_masking_and_fresnel_simplifies_to():
    ggx = NDFS["ggx"](0.4, 0.2)
    w = _pairs(NDFS["ggx"])
    for m in MASKINGS.values():
        for _, other in m.simplifies_to:
            np.testing.assert_array_equal(m.mu_Lambda(ggx, w), MASKINGS[other].mu_Lambda(ggx, w))
    for cls in FRESNELS.values():
        for values, other in cls.simplifies_to:
            c = np.linspace(0, 1, 17)
            np.testing.assert_allclose(cls(**values).F(c), FRESNELS[other]().F(c), rtol=1e-15)


def test_sample_visible_only_where_implemented():
    have = {n for n, c in NDFS.items() if c.sample_visible is not None}
    assert {"ggx", "beckmann"} <= have
    v = direction_deg(np.array([0.0, 40.0, 85.0]), 30.0)
    u = RNG.uniform(0, 1, (200, 3))
    for n in have:
        m = NDFS[n](0.3, 0.5).sample_visible(v, u)
        assert m.shape == (3, 200, 3)
        assert np.all(np.einsum("kni,ki->kn", m, v) > -1e-12)   # visible: v·m ≥ 0


@pytest.mark.parametrize("alpha", [0.1, 0.5, 1.0])
def test_walter_G1_never_exceeds_1(alpha):
    """Walter's fit has a negative numerator for 1.5497 < a < 1.6: G1 was 1.000048 at
    α = 1, θ = 32.5°. It is bounded at Λ = 0 there (issue: G1 ≤ 1, the definition)."""
    ndf = NDFS["beckmann"](alpha)
    theta = np.linspace(0.0, 90.0, 90001)
    w = direction_deg(theta, 0.0)
    g1 = G1(w[:, 2], MASKINGS["walter"].mu_Lambda(ndf, w))
    assert np.all(g1 <= 1.0)
    w325 = direction_deg(32.5, 0.0)[None]
    assert G1(w325[:, 2], MASKINGS["walter"].mu_Lambda(NDFS["beckmann"](1.0), w325))[0] <= 1.0


def test_registration_of_a_throwaway_entry_is_reversible():
    entry = replace(MASKINGS["karis"], name="karis_copy")
    MASKINGS.register(entry)
    try:
        assert MASKINGS["karis_copy"] is entry
    finally:
        MASKINGS.unregister("karis_copy")
    assert "karis_copy" not in MASKINGS
