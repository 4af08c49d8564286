"""The principled albedo goes through integrate/'s methods like every model's: method,
order, samples and seed are honoured and reported; the methods that do not apply (the
E(μ, α) tables, and auto, which would pick one) are refused with 422 naming ``method``.
References are independent of the quadrature: Monte Carlo (integrate/montecarlo.py)
and, for a Lambertian-only principled model, the closed form E = ρ."""
import numpy as np
import pytest

MODEL = {"model": "principled", "roughness": 0.4, "metallic": 0.3, "sheen": 0.5, "clearcoat": 0.5,
         "clearcoat_gloss": 0.3, "base_color": "0.7,0.5,0.3"}
MU = "0.2,0.6,1"


def _albedo(client, **params):
    return client.get("/api/v1/albedo", params={**MODEL, "mu": MU, **params})


@pytest.mark.parametrize("method", ["mc_uniform", "mc_cosine", "mc_ndf", "mc_vndf"])
def test_monte_carlo_is_what_answers(client, method):
    body = _albedo(client, method=method, samples=4096, seed=3).json()
    assert body["method"] == method and body["samples"] == 4096 and body["seed"] == 3
    again = _albedo(client, method=method, samples=4096, seed=3).json()
    other = _albedo(client, method=method, samples=4096, seed=4).json()
    assert again["E"] == body["E"]                     # same seed, same numbers
    assert other["E"] != body["E"]                     # the seed is used


def test_quadrature_agrees_with_monte_carlo_within_their_errors(client):
    quad = _albedo(client, method="quadrature", tol=1e-5).json()
    mc = _albedo(client, method="mc_cosine", samples=2 ** 18, seed=1).json()
    assert quad["method"] == "quadrature"
    for q, q_err, m, m_err in zip(quad["E"], quad["E_error"], mc["E"], mc["E_error"]):
        assert abs(q - m) <= q_err + 5 * m_err


def test_order_is_honoured(client):
    body = _albedo(client, method="quadrature", order=8).json()
    assert body["order"] == [16, 16, 16]          # one comparison, 8 against 16


def test_lambertian_principled_albedo_is_its_colour(client):
    # the Lambert diffuse lobe alone: f = (1 − metallic)·C/π, so E(μ) = C exactly in
    # each channel
    params = {"model": "principled", "principled_diffuse": "lambert", "lobe": "diffuse",
              "base_color": "0.6,0.3,0.1", "mu": MU, "channel": "g"}
    body = client.get("/api/v1/albedo", params=params).json()
    np.testing.assert_allclose(body["E"], 0.3, atol=1e-6)


@pytest.mark.parametrize("method", ["table", "auto"])
def test_methods_that_do_not_apply_are_refused(client, method):
    r = _albedo(client, method=method)
    assert r.status_code == 422
    assert "method" in r.text and "model=principled" in r.text
