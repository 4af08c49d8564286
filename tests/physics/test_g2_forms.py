"""The G2 forms of g2.py: reciprocity, bounds and orderings, limits, grazing, references.

Forms: separable, direction-correlated with λ(φ) of Ashikhmin
 or van Ginneken, height-correlated, height-direction-correlated
, and Hammon's approximation of the height-correlated GGX visibility.

References are written out here from Λ (the GGX closed form, Heitz 2014 eq. 86), not
from the code's μΛ; orderings are proved in the docstrings.
"""
from __future__ import annotations

import math

import mpmath as mp
import numpy as np
import pytest

from app.physics.brdf import BRDF
from app.physics.fresnel import FRESNELS
from app.physics.g2 import G2_FORMS, LAMBDA_PHIS, azimuth_difference
from app.physics.masking import G1, MASKINGS
from app.physics.ndf import NDFS, make_ndf
from app.physics.vectors import direction_deg

from .conftest import ALPHA_PAIRS, random_upper_directions

SMITH = MASKINGS["smith"]
PHI_FORMS = [name for name, form in G2_FORMS.items() if form.needs_phi]
LAMBDAS = sorted(LAMBDA_PHIS)
# Relative rounding allowance for comparisons of G2 values that are ≤ 1.
EPS = 8 * np.finfo(float).eps


def _has_form(ndf_name, ax, ay) -> bool:
    """Every NDF has an isotropic form; an anisotropic one only where the NDF has it
    (a non-shape-invariant NDF rejects α_x ≠ α_y when constructed)."""
    if ax == ay:
        return True
    try:
        make_ndf(ndf_name, ax, ay)
    except ValueError:
        return False
    return True


# (NDF, α_x, α_y): every registered NDF at the shared α pairs it accepts.
NDF_CASES = [(name, ax, ay) for name in sorted(NDFS) for ax, ay in ALPHA_PAIRS
             if _has_form(name, ax, ay)]
NDF_IDS = [f"{n}-ax{ax:g}-ay{ay:g}" for n, ax, ay in NDF_CASES]


def applies(form, ndf_name, ax, ay):
    return (form.applies_to is None or ndf_name in form.applies_to) and \
        (not form.isotropic_only or ax == ay)


def g2_of(name, ndf, l, v, lambda_name=None):
    """(G2, V) of one form, given directions, from the form's own function."""
    form = G2_FORMS[name]
    fn = LAMBDA_PHIS[lambda_name].fn if lambda_name else None
    return form.G2_and_V(np.maximum(l[..., 2], 0.0), np.maximum(v[..., 2], 0.0),
                         SMITH.mu_Lambda(ndf, l), SMITH.mu_Lambda(ndf, v),
                         phi=azimuth_difference(l, v), ndf=ndf, lambda_phi=fn)


def brdf_with(ndf, g2, lambda_name=None, fresnel="schlick", **fresnel_params):
    fn = LAMBDA_PHIS[lambda_name].fn if lambda_name else None
    return BRDF(ndf, SMITH, G2_FORMS[g2], FRESNELS[fresnel](**fresnel_params), 0.0, fn)


# --------------------------------------------------------------------------- λ(φ)

@pytest.mark.parametrize("phi", [0.0, 1e-8, 0.1, 0.5, 1.0, 2.0, math.pi])
def test_lambda_phi_closed_forms(phi):
    """λ(φ) against and evaluated in mpmath at 30 digits."""
    with mp.workdps(30):
        ash = 1 - mp.exp(-mp.mpf("7.3") * mp.mpf(phi) ** 2)
        vg = mp.mpf("4.41") * phi / (mp.mpf("4.41") * phi + 1)
    assert float(LAMBDA_PHIS["ashikhmin"].fn(phi)) == pytest.approx(float(ash), rel=1e-14, abs=0)
    assert float(LAMBDA_PHIS["van_ginneken"].fn(phi)) == pytest.approx(float(vg), rel=1e-14, abs=0)


@pytest.mark.parametrize("name", LAMBDAS)
def test_lambda_phi_range_and_monotone(name):
    """λ(0) = 0, λ increasing on [0, π], and λ < 1 there (mathematically; Ashikhmin's
    1 − e^{−7.3π²} ≈ 1 − 5e-32 rounds to 1, so that check uses the complement)."""
    phi = np.linspace(0.0, np.pi, 2001)
    lam = LAMBDA_PHIS[name].fn(phi)
    assert lam[0] == 0.0
    assert np.all(np.diff(lam) > 0) or name == "ashikhmin"   # Ashikhmin saturates in float
    assert np.all(np.diff(lam) >= 0)
    assert np.all((lam >= 0) & (lam <= 1))
    # large-φ behaviour: Ashikhmin is 1 to rounding beyond ~128°, van Ginneken is not
    if name == "ashikhmin":
        assert np.exp(-7.3 * np.pi**2) > 0 and lam[-1] == pytest.approx(1.0, abs=1e-15)
    else:
        assert lam[-1] == pytest.approx(4.41 * np.pi / (4.41 * np.pi + 1), rel=1e-15, abs=0)
        assert lam[-1] < 0.94


# ----------------------------------------------------------------------- references

def ggx_Lambda(w, ax, ay):
    """Λ = (−1 + √(1 + (α_x² w_x² + α_y² w_y²)/w_z²))/2 (Heitz 2014 eq. 86), μ > 0."""
    return 0.5 * (-1.0 + np.sqrt(1.0 + ((ax * w[..., 0]) ** 2 + (ay * w[..., 1]) ** 2) / w[..., 2] ** 2))


def reference_G2(name, l, v, ax, ay, lam):
    """The seed's formulas in Λ, for μ_l, μ_v > 0."""
    Ll, Lv = ggx_Lambda(l, ax, ay), ggx_Lambda(v, ax, ay)
    G1l, G1v = 1.0 / (1.0 + Ll), 1.0 / (1.0 + Lv)
    if name == "separable":
        return G1l * G1v
    if name == "height_correlated":
        return 1.0 / (1.0 + Ll + Lv)
    if name == "direction_correlated":
        return lam * G1l * G1v + (1.0 - lam) * np.minimum(G1l, G1v)
    if name == "height_direction_correlated":
        return 1.0 / (1.0 + np.maximum(Ll, Lv) + lam * np.minimum(Ll, Lv))
    if name == "hammon":
        mu_l, mu_v = l[..., 2], v[..., 2]
        return 4 * mu_l * mu_v * 0.5 / ((1 - ax) * 2 * mu_l * mu_v + ax * (mu_l + mu_v))
    raise KeyError(name)


SEED_CASES = [(name, lam, ax, ay) for name in sorted(G2_FORMS) for lam in LAMBDAS
              for ax, ay in [(0.01, 0.01), (0.3, 0.3), (1.0, 1.0), (0.05, 0.5)]
              if applies(G2_FORMS[name], "ggx", ax, ay)]


@pytest.mark.parametrize("name, lambda_name, ax, ay", SEED_CASES)
def test_G2_against_seed_formulas(name, lambda_name, ax, ay, rng):
    """G2 from μ and μΛ equals the seed's formula written with Λ (GGX), rel 1e-12, away
    from grazing (where the Λ form is 0·∞). Every form, where it applies."""
    ndf = make_ndf("ggx", ax, ay)
    l = random_upper_directions(rng, 3000, grazing_fraction=0.0)
    v = random_upper_directions(rng, 3000, grazing_fraction=0.0)
    keep = (l[:, 2] > 1e-3) & (v[:, 2] > 1e-3)
    l, v = l[keep], v[keep]
    lam = LAMBDA_PHIS[lambda_name].fn(azimuth_difference(l, v))
    G2, _ = g2_of(name, ndf, l, v, lambda_name)
    np.testing.assert_allclose(G2, reference_G2(name, l, v, ax, ay, lam), rtol=1e-12, atol=0)


# -------------------------------------------------------------- reciprocity, bounds

def _forms_for(ndf_name, ax, ay):
    return [n for n, f in G2_FORMS.items() if applies(f, ndf_name, ax, ay)]


@pytest.mark.parametrize("ndf_name, ax, ay", NDF_CASES, ids=NDF_IDS)
def test_reciprocity_every_form(ndf_name, ax, ay, rng):
    """G2(l, v) = G2(v, l) and V(l, v) = V(v, l) for every form and λ(φ), and the whole
    f(l, v) = f(v, l) (docs/identities.md §5), with 10 % of directions exactly grazing."""
    ndf = make_ndf(ndf_name, ax, ay)
    l = random_upper_directions(rng, 2000)
    v = random_upper_directions(rng, 2000)
    for name in _forms_for(ndf_name, ax, ay):
        for lam in (LAMBDAS if G2_FORMS[name].needs_phi else [None]):
            G2a, Va = g2_of(name, ndf, l, v, lam)
            G2b, Vb = g2_of(name, ndf, v, l, lam)
            np.testing.assert_allclose(G2a, G2b, rtol=1e-13, atol=0, err_msg=name)
            np.testing.assert_allclose(Va, Vb, rtol=1e-13, atol=0, err_msg=name)
            brdf = brdf_with(ndf, name, lam, f0=0.3, f90=0.9)
            f_lv, f_vl = brdf.f(l, v), brdf.f(v, l)
            assert not np.any(np.isnan(f_lv)), name
            np.testing.assert_allclose(f_lv, f_vl, rtol=1e-12, atol=0, err_msg=name)


@pytest.mark.parametrize("ndf_name, ax, ay", NDF_CASES, ids=NDF_IDS)
def test_bounds_and_orderings(ndf_name, ax, ay, rng):
    """docs/identities.md §6 and the orderings that hold between the forms, for either λ(φ):

    * 0 ≤ G2 ≤ min(G1(l), G1(v)) for every form;
    * separable ≤ height-correlated: (1+Λl)(1+Λv) ≥ 1 + Λl + Λv;
    * separable ≤ direction-correlated ≤ min(G1): a convex combination of G1l·G1v ≤ min
      and min;
    * height-correlated ≤ height-direction-correlated: 1 + M + λm ≤ 1 + M + m
      (M, m = max, min of Λ);
    * direction-correlated ≤ height-direction-correlated (same λ): with
      DC = (1 + m − λm)/((1+M)(1+m)), HDC = 1/(1+M+λm), the difference of the cross
      products is (1+M)(1+m) − (1+m−λm)(1+M+λm) = λm(M − m) + λ²m² ≥ 0;
    * hammon ≤ height-correlated (GGX): lerp(μ, 1, α)² − (α² + (1−α²)μ²) =
      2α(1−α)μ(1−μ) ≥ 0, so each √ of is replaced by something larger.
    Direction-correlated and height-correlated are NOT ordered (see the next test).
    """
    ndf = make_ndf(ndf_name, ax, ay)
    l = random_upper_directions(rng, 4000)
    v = random_upper_directions(rng, 4000)
    G1l = G1(l[:, 2], SMITH.mu_Lambda(ndf, l))
    G1v = G1(v[:, 2], SMITH.mu_Lambda(ndf, v))
    top = np.minimum(G1l, G1v) * (1 + EPS)
    for lam in LAMBDAS:
        G = {name: g2_of(name, ndf, l, v, lam)[0] for name in _forms_for(ndf_name, ax, ay)}
        for name, g in G.items():
            assert np.all(np.isfinite(g)) and np.all(g >= 0), name
            assert np.all(g <= top), name
        up = 1 + EPS
        assert np.all(G["separable"] <= G["height_correlated"] * up)
        assert np.all(G["separable"] <= G["direction_correlated"] * up)
        assert np.all(G["height_correlated"] <= G["height_direction_correlated"] * up)
        assert np.all(G["direction_correlated"] <= G["height_direction_correlated"] * up)
        if "hammon" in G:
            assert np.all(G["hammon"] <= G["height_correlated"] * up)


def test_direction_and_height_correlated_are_not_ordered():
    """At φ = 0 (λ = 0) direction-correlated is min(G1) > height-correlated; at φ = π
    with Ashikhmin (λ ≈ 1) it is separable < height-correlated. Both signs occur, so
    identity 6's ordering does not extend to this pair."""
    ndf = make_ndf("ggx", 0.5)
    l = direction_deg(60.0, 0.0)
    same, opposite = direction_deg(70.0, 0.0), direction_deg(70.0, 180.0)
    dc_same = g2_of("direction_correlated", ndf, l, same, "ashikhmin")[0]
    hc_same = g2_of("height_correlated", ndf, l, same)[0]
    dc_opp = g2_of("direction_correlated", ndf, l, opposite, "ashikhmin")[0]
    hc_opp = g2_of("height_correlated", ndf, l, opposite)[0]
    assert dc_same > hc_same * (1 + 1e-3)
    assert dc_opp < hc_opp * (1 - 1e-3)


# ------------------------------------------------------------------------- limits

@pytest.mark.parametrize("ndf_name, ax, ay", NDF_CASES, ids=NDF_IDS)
@pytest.mark.parametrize("name", PHI_FORMS)
@pytest.mark.parametrize("lambda_name", LAMBDAS)
def test_same_azimuth_gives_min_G1(ndf_name, ax, ay, name, lambda_name, rng):
    """φ = 0 ⇒ λ = 0 ⇒ both direction-correlated forms are min(G1(l), G1(v)):
    the seed's motivating case l = v gives G1(l), not G1(l)²."""
    ndf = make_ndf(ndf_name, ax, ay)
    n = 1000
    phi = rng.uniform(0, 360, n)
    l = direction_deg(rng.uniform(0, 90, n), phi)
    v = direction_deg(rng.uniform(0, 90, n), phi)
    # the cross product of two rounded directions of equal azimuth is rounding noise:
    # φ ≤ 1e-15 rad, so λ(φ) ≤ 4.41e-15 (van Ginneken) and G2 = min(G1) to ~1e-14
    assert np.all(azimuth_difference(l, v) <= 1e-15)
    G2, _ = g2_of(name, ndf, l, v, lambda_name)
    G1l = G1(l[:, 2], SMITH.mu_Lambda(ndf, l))
    G1v = G1(v[:, 2], SMITH.mu_Lambda(ndf, v))
    np.testing.assert_allclose(G2, np.minimum(G1l, G1v), rtol=1e-13, atol=0)


@pytest.mark.parametrize("alpha", [0.05, 0.3, 1.0])
def test_lambda_extremes_reduce_to_the_other_forms(alpha, rng):
    """With λ ≡ 1 direction-correlated is separable and height-direction-correlated is
    height-correlated; with λ ≡ 0 both are min(G1). And at φ = π with Ashikhmin
    (λ = 1 − 5e-32) the same holds to rounding; van Ginneken stays visibly apart."""
    ndf = make_ndf("ggx", alpha)
    l = random_upper_directions(rng, 2000)
    v = random_upper_directions(rng, 2000)
    mu_l, mu_v = l[:, 2], v[:, 2]
    ml_l, ml_v = SMITH.mu_Lambda(ndf, l), SMITH.mu_Lambda(ndf, v)
    G1l, G1v = G1(mu_l, ml_l), G1(mu_v, ml_v)
    one, zero = (lambda p: np.ones_like(p)), (lambda p: np.zeros_like(p))
    phi = azimuth_difference(l, v)

    def form(name, fn, phi=phi):
        return G2_FORMS[name].G2_and_V(mu_l, mu_v, ml_l, ml_v, phi=phi, ndf=ndf, lambda_phi=fn)[0]

    sep = G2_FORMS["separable"].G2_and_V(mu_l, mu_v, ml_l, ml_v)[0]
    hc = G2_FORMS["height_correlated"].G2_and_V(mu_l, mu_v, ml_l, ml_v)[0]
    np.testing.assert_allclose(form("direction_correlated", one), sep, rtol=1e-13)
    np.testing.assert_allclose(form("height_direction_correlated", one), hc, rtol=1e-13)
    np.testing.assert_allclose(form("direction_correlated", zero), np.minimum(G1l, G1v), rtol=1e-13)
    np.testing.assert_allclose(form("height_direction_correlated", zero), np.minimum(G1l, G1v),
                               rtol=1e-13)
    pi = np.full_like(phi, np.pi)
    ash = LAMBDA_PHIS["ashikhmin"].fn
    np.testing.assert_allclose(form("direction_correlated", ash, pi), sep, rtol=1e-13)
    np.testing.assert_allclose(form("height_direction_correlated", ash, pi), hc, rtol=1e-13)
    vg = form("height_direction_correlated", LAMBDA_PHIS["van_ginneken"].fn, pi)
    inner = (mu_l > 0.1) & (mu_v > 0.1)
    assert np.all(vg[inner] > hc[inner])


def test_default_lambda_is_ashikhmin(rng):
    """lambda_phi=None (what BRDF passes unless told otherwise) is Ashikhmin's."""
    ndf = make_ndf("ggx", 0.4)
    l = random_upper_directions(rng, 500)
    v = random_upper_directions(rng, 500)
    for name in PHI_FORMS:
        default = brdf_with(ndf, name, None).evaluate(l, v, ("G2",))["G2"]
        ash = brdf_with(ndf, name, "ashikhmin").evaluate(l, v, ("G2",))["G2"]
        vg = brdf_with(ndf, name, "van_ginneken").evaluate(l, v, ("G2",))["G2"]
        np.testing.assert_array_equal(default, ash)
        assert not np.allclose(default, vg)


def test_phi_is_required():
    """A form that needs φ says so instead of guessing it."""
    for name in PHI_FORMS:
        with pytest.raises(ValueError, match="phi"):
            G2_FORMS[name].G2_and_V(np.ones(2), np.ones(2), np.zeros(2), np.zeros(2),
                                    phi=None, ndf=None, lambda_phi=None)


# ------------------------------------------------------------------------ grazing

GRAZING_THETAS = [0.0, 30.0, 89.0, 89.999999, 90.0]
GRAZING_PHIS = [0.0, 45.0, 90.0, 179.0, 180.0]


@pytest.mark.parametrize("ndf_name, ax, ay",
                         [(n, ax, ay) for n in sorted(NDFS)
                          for ax, ay in [(1e-4, 1e-4), (0.3, 0.3), (1.0, 1.0), (0.05, 0.5)]
                          if _has_form(n, ax, ay)])
def test_grazing_is_finite_without_warnings(ndf_name, ax, ay):
    """Every pair from θ ∈ {0, 30, 89, 90−1e-6, 90}° × φ: no floating-point warning
    (underflow aside), G2 ∈ [0, 1] finite everywhere, G2 = 0 where either direction
    grazes, V finite unless BOTH graze (then +inf, a true divergence, for every form
    but the separable one, whose V = 1/(4 a_l a_v) stays finite)."""
    ndf = make_ndf(ndf_name, ax, ay)
    th, ph = np.meshgrid(GRAZING_THETAS, GRAZING_PHIS)
    dirs = direction_deg(th.ravel(), ph.ravel())
    l = np.repeat(dirs, len(dirs), axis=0)
    v = np.tile(dirs, (len(dirs), 1))
    both = (l[:, 2] == 0) & (v[:, 2] == 0)
    either = (l[:, 2] == 0) | (v[:, 2] == 0)
    for name in _forms_for(ndf_name, ax, ay):
        for lam in (LAMBDAS if G2_FORMS[name].needs_phi else [None]):
            with np.errstate(all="raise", under="ignore"):
                G2, V = g2_of(name, ndf, l, v, lam)
            assert np.all(np.isfinite(G2) & (G2 >= 0) & (G2 <= 1 + EPS)), name
            assert np.all(G2[either] == 0.0), name
            assert np.all(np.isfinite(V[~both])), name
            if name == "separable":
                # G1(l)G1(v)/(4 μl μv) = 1/(4 (μl+μlΛl)(μv+μvΛv)) → 1/(4 μlΛl μvΛv)
                assert np.all(np.isfinite(V[both])), name
            else:
                assert np.all(V[both] == np.inf), name


@pytest.mark.parametrize("name", sorted(G2_FORMS))
@pytest.mark.parametrize("lambda_name", LAMBDAS)
@pytest.mark.parametrize("phi_deg", [0.0, 60.0, 180.0])
def test_visibility_is_continuous_as_one_direction_grazes(name, lambda_name, phi_deg):
    """V(μ_l → 0) tends to the value the form returns at μ_l = 0 (its limit, not a
    special case): V at θ_l = 90° − 1e-7° and at 90° agree to 1e-6 relative."""
    ndf = make_ndf("ggx", 0.3)
    v = direction_deg(50.0, phi_deg)
    at = direction_deg(90.0, 0.0)
    near = direction_deg(90.0 - 1e-7, 0.0)
    V_at = g2_of(name, ndf, at, v, lambda_name)[1]
    V_near = g2_of(name, ndf, near, v, lambda_name)[1]
    assert np.isfinite(V_at) and V_at > 0
    assert float(V_near) == pytest.approx(float(V_at), rel=1e-6)


# ------------------------------------------------------------------ GGX identities

@pytest.mark.parametrize("ax, ay", [(0.05, 0.5), (1.0, 0.1), (0.3, 0.3), (1e-3, 0.8)])
def test_ggx_height_correlated_visibility_anisotropic(ax, ay, rng):
    """Anisotropic GGX: V = 0.5 / (μ_l √(μ_v² + α_x² v_x² + α_y² v_y²) + μ_v √(μ_l² +
    α_x² l_x² + α_y² l_y²)) — with α² (1 − μ²) replaced by α_x² ω_x² + α_y² ω_y²
    (Heitz 2014 eq. 99 with eq. 86; Filament's V_SmithGGXCorrelated_Anisotropic). The
    isotropic case is tested in test_masking.py."""
    ndf = make_ndf("ggx", ax, ay)
    l = random_upper_directions(rng, 2000, grazing_fraction=0.0)
    v = random_upper_directions(rng, 2000, grazing_fraction=0.0)
    _, V = g2_of("height_correlated", ndf, l, v)

    def root(w):
        return np.sqrt(w[:, 2] ** 2 + (ax * w[:, 0]) ** 2 + (ay * w[:, 1]) ** 2)

    ref = 0.5 / (l[:, 2] * root(v) + v[:, 2] * root(l))
    np.testing.assert_allclose(V, ref, rtol=1e-12)


def test_hammon_exact_at_alpha_one_and_near_zero(rng):
    """ replaces √(α² + (1−α²)μ²) by lerp(μ, 1, α): equal at α = 1 (both 1) and at
    α → 0 (both μ). So hammon = height-correlated GGX at α = 1 to rounding, and within
    α(μl + μv)/(2μlμv) of it at α = 1e-4."""
    l = random_upper_directions(rng, 2000, grazing_fraction=0.1)
    v = random_upper_directions(rng, 2000, grazing_fraction=0.1)
    ndf = make_ndf("ggx", 1.0)
    np.testing.assert_allclose(g2_of("hammon", ndf, l, v)[0], g2_of("height_correlated", ndf, l, v)[0],
                               rtol=1e-13, atol=1e-16)
    alpha = 1e-4
    ndf = make_ndf("ggx", alpha)
    keep = (l[:, 2] > 0) & (v[:, 2] > 0)
    l, v = l[keep], v[keep]
    hm = g2_of("hammon", ndf, l, v)[0]
    hc = g2_of("height_correlated", ndf, l, v)[0]
    # 1 − G2_hammon = α(μl + μv − 2μlμv)/(2μlμv + α(…)) ≤ α(μl + μv)/(2μlμv), and
    # hammon ≤ height-correlated ≤ 1: the gap closes like α away from grazing.
    mu_l, mu_v = l[:, 2], v[:, 2]
    bound = alpha * (mu_l + mu_v) / (2 * mu_l * mu_v)
    assert np.all(hc - hm >= -EPS) and np.all(hc - hm <= bound * (1 + EPS))
    assert np.all(1 - hc <= bound)


def test_hammon_is_flagged_and_rejects_anisotropy():
    form = G2_FORMS["hammon"]
    assert form.applies_to == ("ggx",) and form.isotropic_only and form.reference
    ndf = make_ndf("ggx", 0.2, 0.5)
    with pytest.raises(ValueError, match="isotropic"):
        form.G2_and_V(np.ones(1), np.ones(1), np.zeros(1), np.zeros(1), phi=None, ndf=ndf,
                      lambda_phi=None)


def test_every_form_has_a_reference():
    for form in G2_FORMS.values():
        assert form.label and form.description and form.reference
    for lam in LAMBDA_PHIS.values():
        assert lam.label and lam.description and lam.reference
