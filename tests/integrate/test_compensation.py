"""Kulla-Conty compensation: the white furnace for every NDF, F̄, the Fresnel factor,
reciprocity (docs/identities.md §5, §7).

References are independent of the code under test: E_single by the reference quadrature
(albedo.py), the albedo of f_ms by Gauss-Legendre over μ_l of the lobe function itself
(not the closed form 1 − E), F̄ by scipy.integrate.quad, F_ms by summing the series."""
import numpy as np
import pytest
from scipy.integrate import quad

from app.integrate import tables
from app.integrate.tables import table as etable
from app.integrate.albedo import albedo
from app.integrate.compensation import fresnel_factor
from app.errors import ParameterError
from app.model import make_spec
from app.physics.fresnel import FRESNELS
from app.physics.ndf import NDFS


@pytest.fixture
def small_tables(monkeypatch):
    """16×16 tables: the furnace must hold within the reported error at any size; the
    smaller size keeps six NDFs' builds to seconds."""
    monkeypatch.setattr(etable, "TABLE_N_Y", 16)
    monkeypatch.setattr(etable, "TABLE_N_R", 16)
    monkeypatch.setattr(etable, "SLOW_TABLE_N", 16)
    tables.table_for_key.cache_clear()
    yield
    tables.table_for_key.cache_clear()


def ms_albedo_numeric(brdf, mu_v, n=400):
    """∫ f_ms(μ_l, μ_v) μ_l dω_l = 2π ∫₀¹ f_ms μ_l dμ_l (f_ms has no azimuth), Gauss-Legendre."""
    x, w = np.polynomial.legendre.leggauss(n)
    mu_l, w = 0.5 * (x + 1.0), 0.5 * w
    f = brdf.multiscatter(mu_l[:, None], np.asarray(mu_v)[None, :])
    return 2.0 * np.pi * np.sum(f * (mu_l * w)[:, None], axis=0)


# Every NDF whose own Λ is exact Smith; Blinn-Phong (Walter's approximate Λ, E > 1) is
# refused with masking=smith (test below); with smith_numeric its table takes minutes.
@pytest.mark.parametrize("ndf", [n for n, c in NDFS.items() if c.smith_exact])
@pytest.mark.parametrize("alpha", [0.15, 0.65])
def test_white_furnace_every_ndf(small_tables, ndf, alpha):
    brdf = make_spec(ndf=ndf, alpha=alpha, fresnel="none", multiscatter="kulla_conty").brdf()
    mu = np.array([0.013, 0.11, 0.37, 0.58, 0.83, 0.97])
    single = albedo(brdf.single(), mu, tol=1e-7)
    E = single.E + ms_albedo_numeric(brdf, mu)
    bound = brdf.multiscatter.error + single.E_error + 1e-9
    assert np.all(np.abs(E - 1.0) <= bound), (E - 1.0, bound)
    # and the compensation is doing something: the single-scattering albedo was below 1
    assert np.min(single.E) < 1.0 - 10 * np.max(bound) or alpha < 0.2


def test_furnace_two_lobes(small_tables):
    brdf = make_spec(ndf="ggx", alpha=0.9, alpha2=0.2, lobe_mix=0.3, fresnel="none",
                     multiscatter="kulla_conty").brdf()
    mu = np.array([0.07, 0.5, 0.9])
    single = albedo(brdf.single(), mu, tol=1e-7)
    E = single.E + ms_albedo_numeric(brdf, mu)
    assert np.all(np.abs(E - 1.0) <= brdf.multiscatter.error + single.E_error + 1e-9)


@pytest.mark.parametrize("f0,f90,p", [(0.04, 1.0, 5.0), (0.9, 0.5, 2.0), (0.3, 1.0, 7.5)])
def test_F_avg_schlick_closed_form(f0, f90, p):
    F = FRESNELS["schlick"](f0=f0, f90=f90, fresnel_p=p)
    ref = 2.0 * quad(lambda m: float(F.F(m)) * m, 0.0, 1.0, epsabs=1e-13)[0]
    assert F.F_avg() == pytest.approx(ref, abs=1e-12)
    if p == 5.0 and f90 == 1.0:
        assert F.F_avg() == pytest.approx((20 * f0 + 1) / 21, abs=1e-15)


def test_F_avg_dielectric_quadrature():
    F = FRESNELS["dielectric"](ior=1.5)
    ref = 2.0 * quad(lambda m: float(F.F(m)) * m, 0.0, 1.0, epsabs=1e-13)[0]
    assert F.F_avg() == pytest.approx(ref, abs=1e-9)


@pytest.mark.parametrize("F_avg,E_avg", [(1.0, 0.7), (0.3, 0.9), (0.95, 0.4)])
def test_fresnel_factor_is_the_series(F_avg, E_avg):
    # energy after bounce k+1, per unit lost by the first (1 − Ē): Ē F̄^{k+1} (1 − Ē)^k
    k = np.arange(1, 2000)
    series = np.sum(F_avg * E_avg * F_avg ** k * (1 - E_avg) ** k) / (1 - E_avg)
    assert fresnel_factor(F_avg, E_avg) == pytest.approx(series, rel=1e-12)


def test_reciprocity_with_compensation():
    brdf = make_spec(ndf="ggx", alpha=0.6, fresnel="schlick", f0=0.5,
                     multiscatter="kulla_conty").brdf()
    rng = np.random.default_rng(7)
    def dirs(n):
        mu = rng.uniform(0.01, 1, n); phi = rng.uniform(0, 2 * np.pi, n)
        s = np.sqrt(1 - mu * mu)
        return np.stack([s * np.cos(phi), s * np.sin(phi), mu], -1)
    l, v = dirs(200), dirs(200)
    f_lv, f_vl = brdf.f(l, v), brdf.f(v, l)
    assert np.allclose(f_lv, f_vl, rtol=1e-12, atol=0)
    assert np.all(f_lv > brdf.single().f(l, v))   # the lobe adds energy everywhere


def test_compensation_refuses_approximate_smith():
    with pytest.raises(ParameterError) as exc:
        make_spec(ndf="blinn_phong", alpha=0.5, multiscatter="kulla_conty")
    assert exc.value.param == "multiscatter"


def test_compensation_refuses_anisotropy():
    with pytest.raises(ParameterError) as exc:
        make_spec(ndf="ggx", alpha=0.5, alpha_y=0.2, multiscatter="kulla_conty")
    assert exc.value.param == "multiscatter"
