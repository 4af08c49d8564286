"""GET /api/v1/g2, /api/v1/fresnel and their figures: contract, reference values, 422s.

Reference values are closed forms written out here: GGX Λ (Heitz 2014 eq. 86), the G2
forms of Heitz 2014, Schlick 1994, the exact dielectric at normal
incidence and at grazing (1).
"""
from __future__ import annotations

import base64
import math

import numpy as np
import pytest
from tests.finite import finite_json


def get(client, url, status=200):
    r = client.get(url)
    assert r.status_code == status, r.text
    return finite_json(r.text)


def plotly_array(value):
    """A Plotly array from figure JSON: a plain list, or a typed array {dtype, bdata}."""
    if isinstance(value, dict) and "bdata" in value:
        a = np.frombuffer(base64.b64decode(value["bdata"]), dtype=value["dtype"])
        return a.reshape(value["shape"]) if "shape" in value else a
    return np.asarray(value, dtype=float)


def ggx_Lambda(theta_deg, alpha):
    t = np.tan(np.deg2rad(theta_deg))
    return (-1 + np.sqrt(1 + alpha**2 * t**2)) / 2


# ----------------------------------------------------------------------------- g2

def test_g2_grid_is_height_correlated_by_default(client):
    body = get(client, "/api/v1/g2?alpha=0.5&n=4")
    assert body["theta_l_deg"] == [0, 30, 60, 90] and body["theta_v_deg"] == [0, 30, 60, 90]
    G2 = np.array(body["G2"], dtype=float)
    assert G2.shape == (4, 4)
    th = np.array(body["theta_l_deg"][:-1])
    L = ggx_Lambda(th, 0.5)
    ref = 1 / (1 + L[:, None] + L[None, :])                      #
    np.testing.assert_allclose(G2[:-1, :-1], ref, rtol=1e-12)
    assert np.all(G2[-1, :] == 0) and np.all(G2[:, -1] == 0)     # G1 = 0 at grazing
    assert G2[0, 0] == 1.0


def test_g2_separable_is_the_product_of_G1(client):
    body = get(client, "/api/v1/g2?g2=separable&ndf=ggx&alpha=0.3&n=7&phi_deg=40")
    G2 = np.array(body["G2"], dtype=float)
    th = np.array(body["theta_l_deg"][:-1])
    G1 = 1 / (1 + ggx_Lambda(th, 0.3))
    np.testing.assert_allclose(G2[:-1, :-1], G1[:, None] * G1[None, :], rtol=1e-12)


@pytest.mark.parametrize("phi_deg, lam", [(0.0, 0.0), (90.0, 1 - math.exp(-7.3 * (math.pi / 2) ** 2))])
def test_g2_direction_correlated_follows_lambda(client, phi_deg, lam):
    """ with Ashikhmin's λ, the default λ(φ): φ = 0 gives min(G1)."""
    body = get(client, f"/api/v1/g2?g2=direction_correlated&alpha=0.4&n=5&phi_deg={phi_deg}")
    G2 = np.array(body["G2"], dtype=float)[:-1, :-1]
    G1 = 1 / (1 + ggx_Lambda(np.array(body["theta_l_deg"][:-1]), 0.4))
    ref = lam * G1[:, None] * G1[None, :] + (1 - lam) * np.minimum(G1[:, None], G1[None, :])
    np.testing.assert_allclose(G2, ref, rtol=1e-12)


def test_g2_hammon_is_reachable_and_bounded(client):
    hm = np.array(get(client, "/api/v1/g2?g2=hammon&alpha=0.3&n=10")["G2"], dtype=float)
    hc = np.array(get(client, "/api/v1/g2?g2=height_correlated&alpha=0.3&n=10")["G2"], dtype=float)
    assert np.all(hm <= hc + 1e-15) and np.all(hm >= 0)


def test_g2_figure_is_a_heatmap(client):
    fig = get(client, "/api/v1/figures/g2?n=5&phi_deg=30&g2=height_direction_correlated")
    (trace,) = fig["data"]
    assert trace["type"] == "heatmap" and trace["colorscale"] == "Cividis"
    assert trace["colorbar"]["title"]["text"] == "G2"
    assert (trace["zmin"], trace["zmax"]) == (0.0, 1.0)
    assert plotly_array(trace["z"]).shape == (5, 5)
    assert "height-direction-correlated" in fig["layout"]["title"]["text"]
    assert "degrees" in fig["layout"]["xaxis"]["title"]["text"]


@pytest.mark.parametrize("query, param, needle", [
    ("n=1", "n", "n"),
    ("n=abc", "n", "n"),
    ("phi_deg=400", "phi_deg", "[-360, 360]"),
    ("phi_deg=nan", "phi_deg", "finite"),
])
def test_g2_rejects_bad_queries(client, query, param, needle):
    r = client.get(f"/api/v1/g2?{query}")
    assert r.status_code == 422, r.text
    detail = r.json()["detail"][0]
    assert detail["loc"][-1] == param and needle in detail["msg"]


def test_g2_grid_limit_counts_n_squared(small_client):
    """Settings.max_grid_points = 100 here: n = 10 (100 points) passes, n = 11 does not."""
    assert small_client.get("/api/v1/g2?n=10").status_code == 200
    r = small_client.get("/api/v1/g2?n=11")
    assert r.status_code == 422
    detail = r.json()["detail"][0]
    assert detail["loc"][-1] == "n" and "121" in detail["msg"] and "BRDF_MAX_GRID_POINTS" in detail["msg"]
    assert small_client.get("/api/v1/figures/g2?n=11").status_code == 422


# ------------------------------------------------------------------------- fresnel

def test_fresnel_schlick_with_exact_and_error(client):
    body = get(client, "/api/v1/fresnel?n=7&f0=0.04")
    theta = np.deg2rad(body["theta_deg"])
    c = np.cos(theta)
    c[-1] = 0.0
    F = np.array(body["F"])
    np.testing.assert_allclose(F, 0.04 + 0.96 * (1 - c) ** 5, rtol=1e-12, atol=1e-15)
    assert body["F_exact_model"] == {"fresnel": "dielectric", "ior": pytest.approx(1.5, rel=1e-14, abs=0)}
    F_exact = np.array(body["F_exact"])
    assert F_exact[0] == pytest.approx(0.04, rel=1e-13, abs=0) and F_exact[-1] == 1.0
    np.testing.assert_allclose(body["F_error"], F - F_exact, rtol=0, atol=1e-16)
    assert body["F_error"][0] == pytest.approx(0.0, abs=1e-15)
    assert body["F_avg"] == pytest.approx((20 * 0.04 + 1) / 21, rel=1e-14, abs=0)   # p = 5, F90 = 1


def test_fresnel_schlick_exponent(client):
    body = get(client, "/api/v1/fresnel?n=3&f0=0.2&f90=0.7&fresnel_p=2")
    assert body["F"][1] == pytest.approx(0.2 + 0.5 * (1 - math.cos(math.pi / 4)) ** 2, rel=1e-12,
                                         abs=0)
    assert body["F_avg"] == pytest.approx(0.2 + 2 * 0.5 / (3 * 4), rel=1e-14, abs=0)


def test_fresnel_exact_forms_have_no_error_curve(client):
    d = get(client, "/api/v1/fresnel?n=5&fresnel=dielectric&ior=2.42")
    assert set(d) == {"theta_deg", "F", "F_avg"}
    assert d["F"][0] == pytest.approx((1.42 / 3.42) ** 2, rel=1e-13, abs=0) and d["F"][-1] == 1.0
    m = get(client, "/api/v1/fresnel?n=5&fresnel=conductor&ior=0.43&k=2.455")
    assert m["F"][0] == pytest.approx((0.57**2 + 2.455**2) / (1.43**2 + 2.455**2), rel=1e-13, abs=0)
    assert m["F"][-1] == 1.0
    assert get(client, "/api/v1/fresnel?n=4&fresnel=none")["F"] == [1.0] * 4


def test_fresnel_schlick_of_a_perfect_mirror_is_finite_json(client):
    """f0 = 1 ⇒ η = ∞: the exact form is 1 everywhere; η is sent as null, nothing breaks."""
    body = get(client, "/api/v1/fresnel?n=4&f0=1")
    assert body["F_exact"] == [1.0] * 4 and body["F_exact_model"]["ior"] is None
    get(client, "/api/v1/figures/fresnel?n=4&f0=1")


def test_fresnel_figure(client):
    fig = get(client, "/api/v1/figures/fresnel?n=11")
    names = [t["name"] for t in fig["data"]]
    assert len(fig["data"]) == 3 and any("exact dielectric" in n for n in names)
    assert fig["data"][2]["yaxis"] == "y2" and "yaxis2" in fig["layout"]
    lo, hi = fig["layout"]["yaxis2"]["range"]          # error axis: 0 at mid-height
    err = get(client, "/api/v1/fresnel?n=11")["F_error"]
    assert lo == -hi and hi >= max(abs(e) for e in err) > 0
    assert "Schlick F₀=0.04" in fig["layout"]["title"]["text"]
    fig = get(client, "/api/v1/figures/fresnel?n=11&fresnel=conductor")
    assert len(fig["data"]) == 1 and "Conductor η=" in fig["layout"]["title"]["text"]


@pytest.mark.parametrize("query, param, needle", [
    ("n=1", "n", "n"),
    ("fresnel=dielectric&ior=0.5", "ior", "[1, 4]"),
    ("fresnel=conductor&ior=11", "ior", "[0.01, 10]"),
    ("fresnel=conductor&k=-1", "k", "[0, 20]"),
    ("fresnel_p=11", "fresnel_p", "[1, 10]"),
    ("fresnel_p=0.5", "fresnel_p", "[1, 10]"),
    ("ior=1.5", "ior", "fresnel=dielectric"),
    ("fresnel=dielectric&f0=0.3", "f0", "fresnel=schlick"),
    ("fresnel=dielectric&k=1", "k", "fresnel=conductor"),
])
def test_fresnel_rejects_bad_queries(client, query, param, needle):
    r = client.get(f"/api/v1/fresnel?{query}")
    assert r.status_code == 422, r.text
    detail = r.json()["detail"][0]
    assert detail["loc"][-1] == param and needle in detail["msg"], detail


def test_fresnel_curve_limit(small_client):
    assert small_client.get("/api/v1/fresnel?n=50").status_code == 200
    r = small_client.get("/api/v1/fresnel?n=51")
    assert r.status_code == 422 and r.json()["detail"][0]["loc"][-1] == "n"


# -------------------------------------------------------------------------- models

def test_models_lists_the_new_choices_with_ranges(client):
    options = get(client, "/api/v1/models")["options"]
    g2 = {c["name"]: c for c in options["g2"]["choices"]}
    assert set(g2) >= {"separable", "height_correlated", "direction_correlated",
                       "height_direction_correlated", "hammon"}
    assert g2["hammon"]["applies_to"] == ["ggx"] and g2["hammon"]["reference"]
    fresnel = {c["name"]: {p["name"]: (p["lo"], p["hi"], p["default"]) for p in c["params"]}
               for c in options["fresnel"]["choices"]}
    assert fresnel["schlick"]["fresnel_p"] == (1.0, 10.0, 5.0)
    assert fresnel["dielectric"] == {"ior": (1.0, 4.0, 1.5)}
    assert fresnel["conductor"] == {"ior": (0.01, 10.0, 0.43), "k": (0.0, 20.0, 2.455)}


@pytest.mark.parametrize("g2", ["direction_correlated", "height_direction_correlated", "hammon"])
def test_eval_with_new_g2_forms_is_reciprocal(client, g2):
    q = "theta_i_deg=10,50,89,90&phi_i_deg=0,30,200,10&theta_o_deg=70,20,90,45&phi_o_deg=180,100,0,300"
    swapped = "theta_i_deg=70,20,90,45&phi_i_deg=180,100,0,300&theta_o_deg=10,50,89,90&phi_o_deg=0,30,200,10"
    a = get(client, f"/api/v1/eval?g2={g2}&quantities=f,G2&{q}")
    b = get(client, f"/api/v1/eval?g2={g2}&quantities=f,G2&{swapped}")
    np.testing.assert_allclose(a["G2"], b["G2"], rtol=1e-13)
    np.testing.assert_allclose(a["f"], b["f"], rtol=1e-12)
