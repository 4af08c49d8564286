"""model=principled through the API: /eval per channel against the material, the lobe
views, the stacked albedo (lobes sum to the total), refusals that name the parameter."""
from __future__ import annotations

import numpy as np

from app.principled import Principled

from .references import DEFAULTS, disney


def test_eval_f_rgb_matches_disney_brdf(client):
    params = {"model": "principled", "base_color": "0.9,0.4,0.2", "metallic": 0.4, "sheen": 0.6,
              "clearcoat": 0.8, "subsurface": 0.3, "roughness": 0.4, "theta_i_deg": "20,60",
              "theta_o_deg": "30,45", "phi_o_deg": "180,90", "quantities": "f,f_rgb,f_diffuse"}
    body = client.get("/api/v1/eval", params=params).json()
    p = {**DEFAULTS, "base_color": (0.9, 0.4, 0.2), "metallic": 0.4, "sheen": 0.6, "clearcoat": 0.8,
         "subsurface": 0.3, "roughness": 0.4}
    d = lambda t, ph: np.array([np.sin(np.radians(t)) * np.cos(np.radians(ph)),
                                np.sin(np.radians(t)) * np.sin(np.radians(ph)), np.cos(np.radians(t))])
    want = np.array([disney(d(20, 0), d(30, 180), p), disney(d(60, 0), d(45, 90), p)])
    np.testing.assert_allclose(body["f_rgb"], want, rtol=1e-10)
    np.testing.assert_allclose(body["f"], want @ [0.2126, 0.7152, 0.0722], rtol=1e-10)


def test_lobes_stack_to_the_total(client):
    body = client.get("/api/v1/principled_albedo", params={"model": "principled", "sheen": 1,
                                                           "clearcoat": 1, "n": 7}).json()
    total = sum(np.asarray(body["lobes"][k]["E"]) for k in ("diffuse", "sheen", "specular", "clearcoat"))
    np.testing.assert_allclose(total, body["E"], rtol=1e-12)
    fig = client.get("/api/v1/figures/principled_albedo", params={"model": "principled"}).json()
    assert [t.get("stackgroup") for t in fig["data"][:4]] == ["albedo"] * 4


def test_every_view_draws_one_lobe(client):
    size = {"lobe": {"n": 31}, "lobe3d": {"n_theta": 8, "n_phi": 16}, "slice": {"n": 16},
            "sphere": {"n": 16}, "albedo": {"n": 5}}
    for view in size:
        for lobe in ("diffuse", "specular", "clearcoat", "sheen"):
            r = client.get(f"/api/v1/{view}", params={"model": "principled", "lobe": lobe,
                                                      "clearcoat": 1, "sheen": 1, **size[view]})
            assert r.status_code == 200, (view, lobe, r.text)


def test_parameter_edges_through_the_api(client):
    for value in (0.0, 1.0):
        params = {"model": "principled", "base_color": f"{value},{value},{value}",
                  "roughness": max(value, 0.01), **{k: value for k in DEFAULTS
                                                    if k not in ("base_color", "roughness")}}
        r = client.get("/api/v1/eval", params={**params, "theta_i_deg": "0,89,90", "theta_o_deg": "89,0,45",
                                               "quantities": "f_rgb"})
        assert r.status_code == 200, r.text
        assert np.all(np.isfinite(np.asarray(r.json()["f_rgb"], dtype=float)))


def test_refusals_name_the_parameter(client):
    cases = [({"model": "principled", "base_color": "1,1"}, "base_color"),
             ({"model": "principled", "kd": 0.5}, "kd"),
             ({"metallic": 0.5}, "metallic"),
             ({"model": "principled", "metallic": 1.5}, "metallic"),
             ({"model": "principled", "anisotropic": 0.5, "principled_multiscatter": "kulla_conty"},
              "principled_multiscatter")]
    for params, name in cases:
        r = client.get("/api/v1/eval", params=params)
        assert r.status_code == 422 and name in r.text, (params, r.text)
    assert Principled().f_rgb(np.array([0, 0, 1.0]), np.array([0, 0, 1.0])).shape == (3,)
