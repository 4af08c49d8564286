"""The principled BRDF's EON diffuse takes the colour inside its definition (issue 34):
f = ρ f_FON(1) + ρ_ms/π (1 − E_F(μ_l))(1 − E_F(μ_v))/(1 − Ē_F), ρ_ms = ρ² Ē_F/(1 − ρ(1 − Ē_F))
(Portsmouth, Kutz & Hill 2025, "EON", JCGT 14(1), eqs. for FON, E_FON and f_ms), written
here from the paper, not from app/physics/diffuse/eon.py."""
from __future__ import annotations

import math
import warnings

import numpy as np
import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.main import create_app
from tests.budget import settings_for_tests

COLOUR = (0.5, 0.2, 0.8)
R = 0.7


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(settings_for_tests()))


def A(r):
    return 1.0 / (1.0 + (0.5 - 2.0 / (3.0 * math.pi)) * r)


def f_fon(r, l, v):
    """Fujii's Oren–Nayar at ρ = 1: A (1 + r s/t)/π, s = l·v − μ_l μ_v, t = max(μ) if s > 0."""
    s = np.dot(l, v) - l[2] * v[2]
    t = max(l[2], v[2]) if s > 0 else 1.0
    return A(r) * (1.0 + r * s / t) / math.pi


def E_fon(r, mu):
    """The paper's closed form E_FON(μ) = A + B G(θ)/π, B = r A."""
    theta = math.acos(mu)
    s, c = math.sin(theta), math.cos(theta)
    G = s * (theta - s * c) + 2.0 / 3.0 * (s / c) * (1.0 - s ** 3) - 2.0 / 3.0 * s
    return A(r) + r * A(r) * G / math.pi


def E_fon_avg(r):
    return A(r) + (2.0 / 3.0 - 28.0 / (15.0 * math.pi)) * r * A(r)


def eon(rho, r, l, v):
    avg = E_fon_avg(r)
    rho_ms = rho * rho * avg / (1.0 - rho * (1.0 - avg))
    return (rho * f_fon(r, l, v)
            + rho_ms / math.pi * (1.0 - E_fon(r, l[2])) * (1.0 - E_fon(r, v[2])) / (1.0 - avg))


def direction(theta_deg, phi_deg):
    t, p = math.radians(theta_deg), math.radians(phi_deg)
    return np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])


def test_closed_form_E_fon_matches_quadrature_of_f_fon():
    # the test's own E_FON checked against integrating its own f_FON (independence of both)
    mu_v = math.cos(math.radians(50.0))
    v = direction(50.0, 0.0)
    n = 400
    mus = (np.arange(n) + 0.5) / n
    phis = (np.arange(2 * n) + 0.5) / (2 * n) * 2 * math.pi
    total = 0.0
    for mu in mus:
        st = math.sqrt(1 - mu * mu)
        total += sum(f_fon(R, np.array([st * math.cos(p), st * math.sin(p), mu]), v) * mu for p in phis)
    total *= (1.0 / n) * (2 * math.pi / (2 * n))
    assert total == pytest.approx(E_fon(R, mu_v), rel=2e-3)


@pytest.mark.parametrize("ti,to,phi_o", [(30.0, 60.0, 180.0), (10.0, 75.0, 90.0), (70.0, 20.0, 30.0)])
def test_principled_eon_diffuse_takes_the_colour_inside(client, ti, to, phi_o):
    r = client.get("/api/v1/eval", params=dict(
        model="principled", principled_diffuse="eon", lobe="diffuse", roughness=R,
        base_color=",".join(map(str, COLOUR)), theta_i_deg=ti, phi_i_deg=0.0,
        theta_o_deg=to, phi_o_deg=phi_o, quantities="f_rgb"))
    assert r.status_code == 200, r.text
    got = np.array(r.json()["f_rgb"][0])
    l, v = direction(ti, 0.0), direction(to, phi_o)
    want = np.array([eon(rho, R, l, v) for rho in COLOUR])
    assert got == pytest.approx(want, rel=1e-9)


def test_principled_eon_albedo_is_not_the_colour(client):
    # E(μ) = ρ E_F + ρ_ms (1 − E_F): not ρ (that was E of "EON at ρ = 1 times the colour")
    r = client.get("/api/v1/principled_albedo", params=dict(
        model="principled", principled_diffuse="eon", roughness=R, sheen=0, specular=0,
        base_color=",".join(map(str, COLOUR)), channel="g"))
    assert r.status_code == 200, r.text
    body = r.json()
    E = np.array(body["lobes"]["diffuse"]["E"])
    mu = np.array(body["mu"])
    rho = COLOUR[1]
    avg = E_fon_avg(R)
    rho_ms = rho * rho * avg / (1.0 - rho * (1.0 - avg))
    want = np.array([rho * E_fon(R, m) + rho_ms * (1 - E_fon(R, m)) if m > 1e-9 else np.nan for m in mu])
    ok = np.isfinite(want)
    assert E[ok] == pytest.approx(want[ok], abs=1e-6)
    assert np.all(np.abs(E[ok] - rho) > 1e-3)
