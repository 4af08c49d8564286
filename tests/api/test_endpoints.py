"""The REST API's contract: shapes, reference values, nulls for divergences.

Reference values are closed forms written out here (docs/conventions.md), not the code's output.
"""
import json
import math

import numpy as np
import pytest
from tests.finite import finite_json


def get(client, url, status=200):
    r = client.get(url)
    assert r.status_code == status, r.text
    return finite_json(r.text)


def test_health(client):
    body = get(client, "/api/v1/health")
    assert body["status"] == "ok" and body["version"]


def test_models_lists_every_option_with_ranges(client):
    body = get(client, "/api/v1/models")
    options = body["options"]
    assert [c["name"] for c in options["ndf"]["choices"]][:2] == ["ggx", "beckmann"]
    assert {c["name"] for c in options["g2"]["choices"]} >= {"separable", "height_correlated"}
    assert {c["name"] for c in options["fresnel"]["choices"]} >= {"none", "schlick"}
    assert options["masking"]["default"] == "smith"
    alpha = next(p for p in body["params"] if p["name"] == "alpha")
    assert (alpha["lo"], alpha["hi"], alpha["default"]) == (1e-4, 1.0, 0.3)
    schlick = next(c for c in options["fresnel"]["choices"] if c["name"] == "schlick")
    assert {p["name"]: p["default"] for p in schlick["params"]} == {"f0": 0.04, "f90": 1.0,
                                                                  "fresnel_p": 5.0}
    for choice in options["ndf"]["choices"]:
        assert choice["label"] and choice["description"] and choice["reference"]


@pytest.mark.parametrize("alpha", [0.05, 0.3, 1.0])
def test_eval_at_normal_incidence_is_the_closed_form(client, alpha):
    # l = v = n: h = n, D_GGX(n) = 1/(π α²), G2 = 1, F = f0  →  f = f0 / (4 π α²)
    body = get(client, f"/api/v1/eval?alpha={alpha}&theta_i_deg=0&theta_o_deg=0&phi_o_deg=0&f0=0.5")
    assert body["D"][0] == pytest.approx(1 / (math.pi * alpha**2), rel=1e-12)
    assert body["f"][0] == pytest.approx(0.5 / (4 * math.pi * alpha**2), rel=1e-12)
    assert body["G2"][0] == pytest.approx(1.0) and body["F"][0] == pytest.approx(0.5)


def test_eval_broadcasts_a_scalar_and_returns_only_what_was_asked(client):
    body = get(client, "/api/v1/eval?theta_i_deg=10,20,30&theta_o_deg=40&quantities=f,D")
    assert set(body) == {"f", "D"} and len(body["f"]) == 3


def test_eval_both_grazing_is_null_and_one_grazing_is_finite(client):
    # Both directions graze in the same direction: height-correlated f diverges (GGX D > 0
    # at the horizon) → null. One grazing: finite, G1 = 0 there.
    body = get(client, "/api/v1/eval?theta_i_deg=90,90&phi_i_deg=0&theta_o_deg=90,45&phi_o_deg=0,180")
    assert body["f"][0] is None
    assert body["f"][1] is not None and body["f"][1] > 0
    assert body["G1_i"][1] == 0.0


def test_eval_opposite_directions_give_zero(client):
    # l = −v (both on the horizon, opposite azimuths): h undefined, specular term 0.
    body = get(client, "/api/v1/eval?theta_i_deg=90&phi_i_deg=0&theta_o_deg=90&phi_o_deg=180")
    assert body["f"] == [0.0] and body["D"] == [0.0]


def test_eval_post_matches_get(client):
    payload = {"ndf": "beckmann", "alpha": 0.2, "theta_i_deg": [10, 50], "phi_i_deg": [0],
               "theta_o_deg": [30, 70], "phi_o_deg": [180, 90]}
    r = client.post("/api/v1/eval", json=payload)
    assert r.status_code == 200, r.text
    g = get(client, "/api/v1/eval?ndf=beckmann&alpha=0.2&theta_i_deg=10,50&phi_i_deg=0"
                    "&theta_o_deg=30,70&phi_o_deg=180,90")
    assert r.json() == g


def test_ndf_curve_endpoints_and_closed_form(client):
    body = get(client, "/api/v1/ndf?ndf=beckmann&alpha=0.5&n=7")
    theta = np.deg2rad(body["theta_deg"])
    assert body["theta_deg"][0] == 0 and body["theta_deg"][-1] == 90
    assert set(np.linspace(0, 90, 7)) <= set(body["theta_deg"])   # the base, plus refinement
    # Beckmann D = exp(−tan²θ/α²)/(π α² cos⁴θ), 0 in the limit θ → 90°
    t = theta[:-1]
    expected = np.exp(-np.tan(t) ** 2 / 0.25) / (math.pi * 0.25 * np.cos(t) ** 4)
    np.testing.assert_allclose(body["D"][:-1], expected, rtol=1e-12)
    assert body["D"][-1] == 0.0


def test_g1_curve_lambda_null_at_grazing(client):
    body = get(client, "/api/v1/g1?alpha=0.4&n=5")
    theta = np.deg2rad(body["theta_deg"][:-1])
    # GGX Λ = (−1 + √(1 + α² tan²θ))/2  (Walter 2007, eq. 34 written with a = 1/(α tanθ))
    expected = (-1 + np.sqrt(1 + 0.16 * np.tan(theta) ** 2)) / 2
    np.testing.assert_allclose(body["Lambda"][:-1], expected, rtol=1e-12, atol=1e-300)
    assert body["Lambda"][-1] is None and body["G1"][-1] == 0.0 and body["G1"][0] == 1.0


def test_lobe_plane_of_incidence_symmetry_and_cosine(client):
    sym = get(client, "/api/v1/lobe?theta_i_deg=0&n=11")
    f = np.array(sym["f"], dtype=float)
    np.testing.assert_allclose(f, f[::-1], rtol=1e-12)
    plain = get(client, "/api/v1/lobe?theta_i_deg=60&n=11")
    cos = get(client, "/api/v1/lobe?theta_i_deg=60&n=11&cosine=true")
    assert "f_cos" in cos and "f" not in cos
    # weighted by the cosine of the varying direction θ_o (what a sampler of v targets),
    # not by the constant cos θ_i
    theta_o = np.array(cos["theta_o_deg"])
    f = get(client, "/api/v1/eval?theta_i_deg=60&phi_i_deg=0&quantities=f"
                    "&theta_o_deg=" + ",".join(repr(float(t)) for t in np.abs(theta_o))
                    + "&phi_o_deg=" + ",".join("180" if t >= 0 else "0" for t in theta_o))["f"]
    np.testing.assert_allclose(cos["f_cos"], np.array(f) * np.cos(np.deg2rad(theta_o)),
                               rtol=1e-12, atol=1e-15)
    # positive θ_o is the mirror side: the peak of a sharp lobe sits at +θ_i
    sharp = get(client, "/api/v1/lobe?alpha=0.05&theta_i_deg=30&n=181")
    assert sharp["theta_o_deg"][int(np.argmax(sharp["f"]))] == pytest.approx(30, abs=0.2)


def test_lobe3d_shape(client):
    body = get(client, "/api/v1/lobe3d?n_theta=4&n_phi=5")
    assert set(np.linspace(0, 90, 4)) <= set(body["theta_deg"])      # the base grid, plus
    assert set(np.linspace(0, 360, 5)) <= set(body["phi_deg"])       # refined rows/columns
    assert np.array(body["f"]).shape == (len(body["theta_deg"]), len(body["phi_deg"]))


def test_albedo_contract(client):
    body = get(client, "/api/v1/albedo?n=5&fresnel=none")
    assert body["mu"] == [0, 0.25, 0.5, 0.75, 1]
    assert body["method"] == "quadrature" and body["evaluations"] > 0 and body["seconds"] > 0
    E, err = np.array(body["E"]), np.array(body["E_error"])
    assert np.all(E >= 0) and np.all(E <= 1 + err)
    assert 0 < body["E_avg"] <= 1 and body["E_avg_error"] < 1e-4
    assert np.all(err < 1e-4)
    # mu wins over n
    mu = get(client, "/api/v1/albedo?n=5&mu=0.3,0.9&fresnel=none")
    assert mu["mu"] == [0.3, 0.9]


def test_albedo_of_a_mirror_is_f0(client):
    # α → 0: every ray reflects once with F(v·h = 1) at normal incidence, G2 → 1: E(1) = f0.
    body = get(client, "/api/v1/albedo?alpha=0.001&mu=1&f0=0.25")
    assert body["E"][0] == pytest.approx(0.25, abs=1e-5)


def test_albedo_includes_diffuse_and_flags_non_conservation(client):
    spec = get(client, "/api/v1/albedo?mu=0.5&fresnel=none")
    both = get(client, "/api/v1/albedo?mu=0.5&fresnel=none&kd=1")
    assert both["E"][0] == pytest.approx(spec["E"][0] + 1.0, abs=1e-12)  # ∫ (1/π) μ_l dl = 1
    fig = get(client, "/api/v1/figures/albedo?mu=0.5,1&fresnel=none&kd=1")
    assert "not energy-conserving" in json.dumps(fig["layout"].get("annotations", []))


@pytest.mark.parametrize("kind", ["lobe", "lobe3d", "ndf", "g1", "albedo"])
def test_figures_are_plotly_json(client, kind):
    fig = get(client, f"/api/v1/figures/{kind}?ndf=beckmann&alpha=0.2")
    assert fig["data"] and fig["layout"]["title"]["text"]
    assert "Beckmann" in fig["layout"]["title"]["text"]


def test_lobe_figure_draws_the_three_directions(client):
    fig = get(client, "/api/v1/figures/lobe?theta_i_deg=40&log=true")
    names = [t["name"] for t in fig["data"]]
    assert {"normal n", "incident l", "mirror"} <= set(names)
    assert fig["layout"]["polar"]["radialaxis"]["type"] == "log"


def test_openapi_schema_lists_every_endpoint(client):
    paths = get(client, "/openapi.json")["paths"]
    for p in ["/api/v1/health", "/api/v1/models", "/api/v1/eval", "/api/v1/ndf", "/api/v1/g1",
              "/api/v1/lobe", "/api/v1/lobe3d", "/api/v1/albedo", "/api/v1/figures/lobe"]:
        assert p in paths


def test_static_page_and_plotly_are_served_locally(client):
    r = client.get("/static/vendor/plotly.min.js")
    assert r.status_code == 200 and r.content[:200].find(b"plotly.js") >= 0
