"""Each diffuse model against its paper's formula (tests/diffuse/references.py), its
albedo against an independent midpoint rule, its parameter edges, its reciprocity and
its scalar form (what the compiled loops call) against numpy."""
from __future__ import annotations

import itertools

import numpy as np
import pytest

from app.model import make_spec
from app.physics.diffuse import DIFFUSES

from .references import REFERENCES, direction, e_fon

NAMES = list(DIFFUSES)
SETTINGS = [dict(alpha=0.05, sigma=0.1, diffuse_roughness=0.1),
            dict(alpha=0.4, sigma=0.6, diffuse_roughness=0.5),
            dict(alpha=1.0, sigma=1.4, diffuse_roughness=1.0)]


def _model(name, s):
    return DIFFUSES[name](alpha=s["alpha"], sigma=s["sigma"], diffuse_roughness=s["diffuse_roughness"])


def _ref_kwargs(s):
    return dict(alpha=s["alpha"], roughness=np.sqrt(s["alpha"]), sigma=s["sigma"],
                diffuse_roughness=s["diffuse_roughness"])


def _angles(n=400, seed=1):
    rng = np.random.default_rng(seed)
    th = rng.uniform(0.0, 0.49 * np.pi, (2, n))
    ph = rng.uniform(-np.pi, np.pi, (2, n))
    return th[0], ph[0], th[1], ph[1]


def test_every_model_is_registered():
    assert NAMES == ["lambert", "burley", "oren_nayar", "eon", "hammon"]


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("s", SETTINGS)
@pytest.mark.parametrize("rho", [0.3, 1.0])
def test_against_the_paper(name, s, rho):
    tl, pl, tv, pv = _angles()
    l, v = direction(tl, pl), direction(tv, pv)
    got = _model(name, s).f(rho, l[:, 2], v[:, 2], np.sum(l * v, axis=-1))
    want = REFERENCES[name](rho, tl, pl, tv, pv, **_ref_kwargs(s))
    np.testing.assert_allclose(got, want, rtol=1e-11, atol=1e-14)


def _midpoint_albedo(name, s, rho, theta_v, n=1200):
    """E = ∫ f μ_l dω_l by the midpoint rule in (μ_l, φ_l) (dω = dμ dφ), paper formula."""
    mu = (np.arange(n) + 0.5) / n
    phi = -np.pi + 2 * np.pi * (np.arange(n) + 0.5) / n
    f = REFERENCES[name](rho, np.arccos(mu)[:, None], phi[None, :], theta_v, 0.0, **_ref_kwargs(s))
    return float(np.sum(f * mu[:, None]) * (1.0 / n) * (2 * np.pi / n))


@pytest.mark.parametrize("name", NAMES)
@pytest.mark.parametrize("s", SETTINGS[1:])
def test_albedo_against_midpoint_rule(name, s):
    thetas = np.deg2rad([5.0, 40.0, 75.0])
    model = _model(name, s)
    E, err = model.albedo(0.8, np.cos(thetas))
    want = [_midpoint_albedo(name, s, 0.8, t) for t in thetas]
    # the midpoint rule's own error is O(1/n²) ≈ 1e-6 (kinks at μ_l = μ_v, cos φ = 0)
    np.testing.assert_allclose(E, want, atol=2e-5 + err)
    assert err < 1e-5


def test_eon_albedo_closed_form_is_fon_albedo():
    """E_F of EON's paper against a quadrature of Fujii's single-scattering lobe."""
    from .references import fon
    n = 1200
    mu = (np.arange(n) + 0.5) / n
    phi = -np.pi + 2 * np.pi * (np.arange(n) + 0.5) / n
    for r in (0.3, 1.0):
        for theta in np.deg2rad([10.0, 60.0, 85.0]):
            f = fon(1.0, np.arccos(mu)[:, None], phi[None, :], theta, 0.0, r)
            E = np.sum(f * mu[:, None]) / n * 2 * np.pi / n
            assert abs(E - e_fon(theta, r)) < 2e-5


@pytest.mark.parametrize("name,conserves", [("lambert", True), ("eon", True), ("burley", False),
                                            ("oren_nayar", False), ("hammon", False)])
def test_white_furnace(name, conserves):
    """ρ = 1: Lambert and EON reflect everything at every view (by the independent
    rule, not the model's own albedo); the others do not, by a stated margin."""
    s = SETTINGS[2]
    assert DIFFUSES[name].conserves_energy is conserves
    E = np.array([_midpoint_albedo(name, s, 1.0, t) for t in np.deg2rad([0.0, 45.0, 80.0])])
    if conserves:
        np.testing.assert_allclose(E, 1.0, atol=2e-5)
    else:
        assert np.max(np.abs(E - 1.0)) > 0.02


@pytest.mark.parametrize("name", NAMES)
def test_reciprocity(name):
    tl, pl, tv, pv = _angles(seed=3)
    spec = make_spec(diffuse=name, kd=0.7, alpha=0.3)
    brdf = spec.brdf()
    l, v = direction(tl, pl), direction(tv, pv)
    a = brdf.evaluate(l, v, ("f", "f_diffuse"))
    b = brdf.evaluate(v, l, ("f", "f_diffuse"))
    np.testing.assert_allclose(a["f_diffuse"], b["f_diffuse"], rtol=1e-12)
    np.testing.assert_allclose(a["f"], b["f"], rtol=1e-10)


@pytest.mark.parametrize("name", NAMES)
def test_parameter_edges_finite(name):
    """Every parameter at its range's ends, ρ ∈ {0, 1}, and directions up to the horizon
    (one of them at a time): f finite and ≥ 0, albedo finite and in [0, 2]."""
    cls = DIFFUSES[name]
    ranges = [(p.name, (p.lo, p.hi)) for p in cls.params] + [("alpha", (1e-4, 1.0))]
    theta = np.deg2rad([0.0, 30.0, 89.0, 90.0])
    tl, tv, dphi = np.meshgrid(theta, theta, np.deg2rad([0.0, 90.0, 180.0]), indexing="ij")
    one_grazes = ~((tl == np.pi / 2) & (tv == np.pi / 2))
    l, v = direction(tl, 0.0 * tl), direction(tv, dphi)
    for values in itertools.product(*[r for _, r in ranges]):
        model = cls(**dict(zip([n for n, _ in ranges], values)))
        for rho in (0.0, 1.0):
            f = model.f(rho, l[..., 2], v[..., 2], np.sum(l * v, axis=-1))
            assert np.all(np.isfinite(f[one_grazes])) and np.all(f[one_grazes] >= 0)
            E, err = model.albedo(rho, np.array([0.0, 0.5, 1.0]))
            assert np.all(np.isfinite(E)) and np.all((E >= 0) & (E <= 2)) and np.isfinite(err)


@pytest.mark.parametrize("name", NAMES)
def test_scalar_form_matches_numpy(name):
    tl, pl, tv, pv = _angles(n=50, seed=5)
    l, v = direction(tl, pl), direction(tv, pv)
    for s in SETTINGS:
        model = _model(name, s)
        p = model.kernel_params()
        for rho in (0.0, 0.5, 1.0):
            got = [model.f_scalar(rho, a[2], b[2], float(a @ b), p) for a, b in zip(l, v)]
            want = model.f(rho, l[:, 2], v[:, 2], np.sum(l * v, axis=-1))
            np.testing.assert_allclose(got, want, rtol=1e-12, atol=1e-15)


def test_lambert_default_unchanged():
    """diffuse=lambert (the default) is the BRDF's own kd/π: the same f as before."""
    tl, pl, tv, pv = _angles(seed=7)
    l, v = direction(tl, pl), direction(tv, pv)
    base = make_spec(kd=0.4).brdf()
    assert base.diffuse is None
    f = base.evaluate(l, v, ("f", "f_diffuse"))
    np.testing.assert_allclose(f["f_diffuse"], 0.4 / np.pi)
    spec_only = make_spec(kd=0.0).brdf().evaluate(l, v)["f"]
    np.testing.assert_allclose(f["f"], spec_only + 0.4 / np.pi, rtol=1e-13)
