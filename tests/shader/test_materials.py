"""Measured materials: exact RGB Fresnel of every preset metal, the artists' forms beside
it, and their E_avg against an independent quadrature."""
from __future__ import annotations

import json

import numpy as np
import pytest

from app import materials
from tests.shader import reference_albedo

DATA = json.loads(materials.DATA.read_text(encoding="utf-8"))
METALS = [m for m in DATA["materials"] if m["kind"] == "conductor"]


def test_data_carries_source_and_licence(client):
    body = client.get("/api/v1/materials").json()
    assert "physicallybased.info" in body["source"] and "CC0" in body["license"]
    assert len(body["materials"]) == 110 and len(METALS) == 32


@pytest.mark.parametrize("metal", METALS, ids=lambda m: m["slug"])
def test_exact_fresnel_at_normal_incidence(metal):
    """F(0°) of the exact conductor Fresnel = ((n − 1)² + k²)/((n + 1)² + k²) per channel."""
    for n, k, fresnel in zip(metal["n"], metal["k"], materials.channel_fresnels(metal)):
        expected = ((n - 1) ** 2 + k ** 2) / ((n + 1) ** 2 + k ** 2)
        assert float(fresnel.F(np.array(1.0))) == pytest.approx(expected, rel=1e-12, abs=1e-15)
        F = fresnel.F(np.linspace(0, 1, 201))
        assert np.all((F >= 0) & (F <= 1)) and float(fresnel.F(np.array(0.0))) == pytest.approx(1.0)


def test_gold_red_channel_n_zero_works(client):
    gold = materials.material("gold")
    assert gold["n"][0] == 0
    red = materials.channel_fresnels(gold)[0]
    assert np.allclose(red.F(np.linspace(0, 1, 50)), 1.0)      # n = 0: total reflection
    res = client.get("/api/v1/materials/fresnel", params={"material": "gold", "alpha": 0.3})
    assert res.status_code == 200
    body = res.json()
    for name, rgb in body["F"].items():
        assert np.all(np.isfinite(np.array(rgb, dtype=float))), name
    assert body["errors"]["gulbrandsen"]["F_max"][0] == 0.0    # the mirror limit, exactly


def test_artists_forms_meet_their_definitions():
    copper = materials.material("copper")
    forms = materials.approximations(copper)
    F0 = materials.f0(copper)
    for c in range(3):
        for name in ("schlick", "f82_tint", "gulbrandsen"):
            assert float(forms[name][c].F(np.array(1.0))) == pytest.approx(F0[c], rel=1e-9)   # F(0°) = F₀
        mu_bar = 1 / 7
        schlick_bar = F0[c] + (1 - F0[c]) * (1 - mu_bar) ** 5
        assert float(forms["f82_tint"][c].F(np.array(mu_bar))) == pytest.approx(copper["f82_tint"][c] * schlick_bar)


def test_dielectric_preset():
    water = materials.material("water")
    assert materials.f0(water)[1] == pytest.approx(((1.3325 - 1) / 2.3325) ** 2)


def test_E_avg_of_a_channel_against_independent_quadrature(client):
    body = client.get("/api/v1/materials/fresnel", params={"material": "copper", "alpha": 0.3, "n": 7}).json()
    from app.model import make_spec
    lobe = make_spec(alpha=0.3).brdf()
    from dataclasses import replace
    for name in ("exact", "schlick"):
        fresnel = materials.approximations(materials.material("copper"))[name][2]
        ref, ref_err = reference_albedo.albedo_average(replace(lobe, fresnel=fresnel))
        assert abs(body["E_avg"][name][2] - ref) <= body["E_avg_error"][name][2] + ref_err


def test_unknown_material_is_a_422_naming_it(client):
    res = client.get("/api/v1/materials/fresnel", params={"material": "unobtainium"})
    assert res.status_code == 422 and res.json()["detail"][0]["loc"][-1] == "material"
    assert "gold" in res.json()["detail"][0]["msg"]


def _eval(client, **query):
    res = client.get("/api/v1/eval", params=query)
    assert res.status_code == 200, res.text
    return res.json()


@pytest.mark.parametrize("slug", ["gold", "silver", "copper", "water"])
def test_eval_answers_rgb_beside_luminance(client, slug):
    """At θ_i = θ_o = 0 (v·h = 1) F_rgb is F₀ per channel from the data's n, k (or ior);
    F and f are the Rec. 709 luminance of F_rgb and f_rgb."""
    record = materials.material(slug)
    body = _eval(client, material=slug, alpha=0.3, theta_i_deg="0,40", phi_i_deg=0, theta_o_deg="0,40",
                 phi_o_deg=180, quantities="f,F")
    if record["kind"] == "conductor":
        n, k = np.array(record["n"]), np.array(record["k"])
        F0 = ((n - 1) ** 2 + k ** 2) / ((n + 1) ** 2 + k ** 2)
    else:
        F0 = np.full(3, ((record["ior"] - 1) / (record["ior"] + 1)) ** 2)
    F_rgb, f_rgb = np.array(body["F_rgb"]), np.array(body["f_rgb"])
    assert F_rgb[0] == pytest.approx(F0, rel=1e-12)
    weights = np.array([0.2126, 0.7152, 0.0722])
    assert body["F"] == pytest.approx((F_rgb @ weights).tolist(), rel=1e-12)
    assert body["f"] == pytest.approx((f_rgb @ weights).tolist(), rel=1e-12)
    # each channel's f is the model with that channel's exact Fresnel as a scalar model
    for c, fresnel in enumerate(materials.channel_fresnels(record)):
        params = {"fresnel": fresnel.name, **{p.name: getattr(fresnel, p.name) for p in fresnel.params}}
        if params.get("ior", 1.0) < 0.01:      # gold's red n = 0 is below the scalar model's range
            continue
        single = _eval(client, alpha=0.3, theta_i_deg="0,40", phi_i_deg=0, theta_o_deg="0,40", phi_o_deg=180,
                       quantities="f", **params)
        assert f_rgb[:, c] == pytest.approx(single["f"], rel=1e-12)


@pytest.mark.parametrize("query, param", [({"material": "gold", "f0": 0.5}, "f0"),
                                          ({"material": "gold", "fresnel": "schlick"}, "fresnel"),
                                          ({"material": "gold", "ior": 1.5}, "ior"),
                                          ({"material": "vibranium"}, "material")])
def test_material_with_its_own_fresnel_parameters_is_a_422(client, query, param):
    res = client.get("/api/v1/eval", params=query)
    assert res.status_code == 422 and res.json()["detail"][0]["loc"][-1] == param


def test_lit_sphere_in_colour(client):
    """Gold's sphere is red > green > blue where lit, its three channels equal without a
    material; outside the disk white; the pixel facing the viewer under a light along the
    view (θ_i = 0) is f_rgb(n, n) cos 0 from /eval, sRGB-encoded."""
    gold = client.get("/api/v1/materials/sphere", params={"material": "gold", "alpha": 0.3, "n": 33,
                                                          "theta_i_deg": 0}).json()
    rgb = np.array(gold["rgb"])
    assert rgb.shape == (33, 33, 3) and (rgb[0, 0] == 255).all()
    centre = rgb[16, 16]
    assert centre[0] > centre[1] > centre[2]
    f = np.array(_eval(client, material="gold", alpha=0.3, theta_i_deg=0, theta_o_deg=0, quantities="f")["f_rgb"][0])
    c = np.clip(f, 0, 1)
    srgb = np.where(c <= 0.0031308, 12.92 * c, 1.055 * c ** (1 / 2.4) - 0.055)
    assert np.abs(centre - np.round(srgb * 255)).max() <= 1      # the centre pixel is 1/33 off the pole
    grey = np.array(client.get("/api/v1/materials/sphere", params={"alpha": 0.3, "n": 17}).json()["rgb"])
    assert (grey[..., 0] == grey[..., 1]).all() and (grey[..., 1] == grey[..., 2]).all()
