"""The environment-lit sphere against independent integrals: under the uniform
environment each pixel is the directional albedo times the radiance (albedo quadrature),
under the overcast sky a Lambertian pixel is ρ/π × the irradiance (brute Monte Carlo of
the sky's formula), within the noise the renderer states; the white furnace vanishes."""
from __future__ import annotations

import numpy as np
import pytest

from app.environment.sphere import sphere_frames
from app.integrate.methods import albedo_by
from app.model import make_spec
from tests.environment.brute_force import render


def test_lambertian_sphere_under_uniform_is_albedo_times_radiance():
    brdf = make_spec(kd=0.7, f0=0.0, f90=0.0).brdf()
    colour = (0.8, 0.5, 0.25)
    out = render(brdf, "uniform", 30.0, 45.0, 48, 16, colour)
    mean_rgb = np.nanmean(out["radiance"].reshape(-1, 3), axis=0)
    np.testing.assert_allclose(mean_rgb, 0.7 * np.array(colour), atol=4 * out["noise"]["mean_radiance_error"] + 1e-12)


def test_glossy_sphere_under_uniform_matches_albedo_per_pixel():
    brdf = make_spec(alpha=0.4, f0=0.04, kd=0.5).brdf()
    out = render(brdf, "uniform", 30.0, 45.0, 40, 32)
    on, frame, _ = sphere_frames(40)
    mu = frame[:, 2, 2]                     # n·v, v = +z
    E = albedo_by(brdf, mu, method="quadrature", tol=1e-5)["E"]
    got = out["radiance"][on][:, 0]
    assert abs(got.mean() - E.mean()) <= 4 * out["noise"]["mean_radiance_error"]
    # per pixel within 5 σ of the stated per-pixel error (worst of ~1250 pixels)
    assert np.max(np.abs(got - E)) <= 5 * out["noise"]["std_error_max"]


def test_lambertian_under_overcast_matches_irradiance():
    from tests.environment.brute_force import uniform_radiance
    brdf = make_spec(kd=1.0, f0=0.0, f90=0.0).brdf()
    out = render(brdf, "overcast", 50.0, 90.0, 24, 64)
    on, frame, _ = sphere_frames(24)
    normals = frame[:, 2, :]
    w, L = uniform_radiance("overcast", 50.0, 90.0, 400_000, 11)
    idx = np.linspace(0, len(normals) - 1, 12).astype(int)
    ref = np.array([np.mean(L * np.clip(w @ normals[i], 0, None)) * 4 * np.pi / np.pi for i in idx])
    got = out["radiance"][on][idx, 0]
    ref_error = 4 * np.pi / np.pi * np.std(L) / np.sqrt(len(w))
    assert np.all(np.abs(got - ref) <= 5 * out["noise"]["std_error_max"] + 5 * ref_error)


def test_white_furnace_sphere_disappears():
    """F = 1, uniform environment, Kulla-Conty: every pixel ≈ the background (1)."""
    brdf = make_spec(alpha=0.5, fresnel="none", multiscatter="kulla_conty").brdf()
    out = render(brdf, "uniform", 30.0, 45.0, 48, 64)
    px = out["radiance"][~np.isnan(out["radiance"][..., 0])][:, 0]
    assert np.all(out["background"] == 1.0)
    table_error = brdf.multiscatter.error
    assert abs(px.mean() - 1.0) <= 4 * out["noise"]["mean_radiance_error"] + table_error
    assert np.max(np.abs(px - 1.0)) <= 5 * out["noise"]["std_error_max"] + table_error
    # without compensation the rough sphere is visibly darker than its background
    single = render(make_spec(alpha=0.5, fresnel="none").brdf(), "uniform", 30.0, 45.0, 48, 64)
    assert np.nanmean(single["radiance"]) < 0.95


@pytest.mark.parametrize("environment", ["point", "uniform", "studio", "overcast", "sunset"])
def test_api_sphere_env_every_environment(environment, client):
    r = client.get("/api/v1/figures/sphere_env", params={"model": "principled", "environment": environment,
                                                         "n": 32, "samples": 8, "clearcoat": 1, "sheen": 1})
    assert r.status_code == 200, r.text
    assert r.json()["data"][0]["source"].startswith("data:image/png;base64,")
    d = client.get("/api/v1/sphere_env", params={"environment": environment, "n": 16, "samples": 8}).json()
    if environment != "point":
        assert d["samples"]["per_pixel"] == 8 and d["noise"]["relative"] >= 0
    bad = client.get("/api/v1/sphere_env", params={"environment": environment, "light_color": "1,2,1"})
    assert bad.status_code == 422 and "light_color" in bad.text


@pytest.mark.parametrize("colour", ["ALPHA", "1,2,1", "1,1", ""])
def test_a_bad_light_colour_is_refused_before_any_work(colour):
    """The view's check refuses it (the fuzz test's oracle, and no render is started)."""
    from app.config import Settings
    from app.errors import ParameterError
    from app.views import VIEWS
    view = VIEWS["sphere_env"]
    with pytest.raises(ParameterError) as exc:
        view.check(view.figure_query(light_color=colour), Settings())
    assert exc.value.param == "light_color"
