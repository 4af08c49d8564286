"""The views a lecture needs: lit sphere, θ_h/θ_d slice, D·cos θ. Checked against
independent constructions (angles from dot products, the BRDF from /eval, the
projected-area identity), not against the code's own output."""
from __future__ import annotations

import math

import numpy as np
import pytest

from app.quantities import rusinkiewicz_directions


def null_to_nan(values):
    return np.array([[math.nan if x is None else x for x in row] for row in values])


def angle_deg(a, b) -> float:
    return math.degrees(math.atan2(np.linalg.norm(np.cross(a, b)), np.dot(a, b)))


def eval_f(client, model: dict, l_local, v_local) -> float:
    """f from /eval for local directions given as unit vectors (n = +z)."""
    def polar(w):
        return angle_deg(w, [0, 0, 1]), math.degrees(math.atan2(w[1], w[0]))
    ti, pi = polar(l_local)
    to, po = polar(v_local)
    r = client.get("/api/v1/eval", params={**model, "theta_i_deg": ti, "phi_i_deg": pi,
                                           "theta_o_deg": to, "phi_o_deg": po, "quantities": "f"})
    assert r.status_code == 200, r.text
    return r.json()["f"][0]


def test_ndf_cosine_integrates_to_one(client):
    # ∫ D(m) cos θ_m dω_m = 1 (Walter et al. 2007, eq. 4); isotropic: 2π ∫ D cos θ sin θ dθ
    for ndf, alpha in (("ggx", 0.3), ("beckmann", 0.5)):
        body = client.get("/api/v1/ndf", params={"ndf": ndf, "alpha": alpha, "n": 4001,
                                                 "cosine": "true"}).json()
        theta = np.radians(body["theta_deg"])
        integral = 2 * np.pi * np.trapezoid(np.array(body["D_cos"]) * np.sin(theta), theta)
        assert integral == pytest.approx(1.0, abs=2e-4)
        plain = client.get("/api/v1/ndf", params={"ndf": ndf, "alpha": alpha, "n": 4001}).json()
        np.testing.assert_allclose(body["D_cos"], np.array(plain["D"]) * np.cos(theta), rtol=1e-12, atol=1e-15)


@pytest.mark.parametrize("theta_i, phi_i", [(40.0, 0.0), (70.0, 120.0)])
def test_lit_sphere_pixels_are_f_cos_at_the_local_angles(client, theta_i, phi_i):
    n = 16
    model = {"ndf": "beckmann", "alpha": 0.4, "kd": 0.3}
    body = client.get("/api/v1/sphere", params={**model, "theta_i_deg": theta_i,
                                                "phi_i_deg": phi_i, "n": n}).json()
    L = null_to_nan(body["radiance"])
    xs, ys = np.array(body["x"]), np.array(body["y"])
    assert L.shape == (n, n) and ys[0] > ys[-1]               # row 0 is the top of the image
    light = np.array([math.sin(math.radians(theta_i)) * math.cos(math.radians(phi_i)),
                      math.sin(math.radians(theta_i)) * math.sin(math.radians(phi_i)),
                      math.cos(math.radians(theta_i))])
    view = np.array([0.0, 0.0, 1.0])
    checked = 0
    for i, j in [(2, 7), (5, 11), (8, 8), (12, 3), (7, 14), (0, 0)]:
        x, y = xs[j], ys[i]
        if x * x + y * y >= 1:
            assert math.isnan(L[i, j])                       # off the sphere: null
            continue
        normal = np.array([x, y, math.sqrt(1 - x * x - y * y)])
        # isotropic BRDF: only the polar angles and the azimuth difference matter
        t_l, t_v = angle_deg(light, normal), angle_deg(view, normal)
        if t_l >= 90:
            assert L[i, j] == 0.0
            continue
        pl, pv = light - normal * light.dot(normal), view - normal * view.dot(normal)
        dphi = angle_deg(pl, pv) if np.linalg.norm(pl) * np.linalg.norm(pv) > 1e-12 else 0.0
        l_loc = [math.sin(math.radians(t_l)), 0.0, math.cos(math.radians(t_l))]
        v_loc = [math.sin(math.radians(t_v)) * math.cos(math.radians(dphi)),
                 math.sin(math.radians(t_v)) * math.sin(math.radians(dphi)), math.cos(math.radians(t_v))]
        expected = eval_f(client, model, l_loc, v_loc) * math.cos(math.radians(t_l))
        assert L[i, j] == pytest.approx(expected, rel=1e-9)
        checked += 1
    assert checked >= 3


def test_rusinkiewicz_angles_round_trip():
    rng = np.random.default_rng(7)
    th, ph, td, pd = (rng.uniform(0, 90, 50), rng.uniform(-180, 180, 50),
                      rng.uniform(0, 90, 50), rng.uniform(-180, 180, 50))
    l, v = rusinkiewicz_directions(th, ph, td, pd)
    for k in range(50):
        h = (l[k] + v[k]) / np.linalg.norm(l[k] + v[k])
        assert np.linalg.norm(l[k]) == pytest.approx(1) and np.linalg.norm(v[k]) == pytest.approx(1)
        assert angle_deg(h, [0, 0, 1]) == pytest.approx(th[k], abs=1e-9)          # θ_h
        assert angle_deg(l[k], h) == pytest.approx(td[k], abs=1e-9)               # θ_d
        if th[k] > 1e-6:
            assert math.degrees(math.atan2(h[1], h[0])) == pytest.approx(ph[k], abs=1e-7)   # φ_h


def test_slice_values_and_horizon(client):
    model = {"ndf": "ggx", "alpha": 0.3}
    n = 7
    body = client.get("/api/v1/slice", params={**model, "n": n, "phi_d_deg": 0}).json()
    f = null_to_nan(body["f"])
    theta = np.array(body["theta_h_deg"])
    for i, td in enumerate(body["theta_d_deg"]):          # rows θ_d
        for j, th in enumerate(theta):                     # columns θ_h
            # φ_d = 0: in the plane of incidence, l at θ_h + θ_d, v at θ_h − θ_d from n
            if th + td > 90 + 1e-9:
                assert math.isnan(f[i, j])                 # l below the horizon: no such pair
                continue
            l_loc = [math.sin(math.radians(th + td)), 0, math.cos(math.radians(th + td))]
            v_loc = [math.sin(math.radians(th - td)), 0, math.cos(math.radians(th - td))]
            expected = eval_f(client, model, l_loc, v_loc)
            if expected is None:                           # l = v grazing: f diverges (null)
                assert math.isnan(f[i, j]) and (th, td) == (90, 0)
            else:
                assert f[i, j] == pytest.approx(expected, rel=1e-9)
