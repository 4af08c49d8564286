"""Bad input gets a 422 (or 413) naming the parameter and what it allows; never a 500."""
import pytest


def detail(r):
    assert r.headers["content-type"].startswith("application/json")
    d = r.json()["detail"]
    return d if isinstance(d, list) else [{"msg": d, "loc": []}]


@pytest.mark.parametrize("query, param, needle", [
    ("alpha=nan", "alpha", "finite"),
    ("alpha=inf", "alpha", "finite"),
    ("alpha=-Infinity", "alpha", "finite"),
    ("alpha=0", "alpha", "[0.0001, 1]"),
    ("alpha=1e308", "alpha", "[0.0001, 1]"),
    ("alpha=abc", "alpha", "alpha"),
    ("alpha_y=2", "alpha_y", "[0.0001, 1]"),
    ("f0=1.5", "f0", "[0, 1]"),
    ("kd=-0.1", "kd", "[0, 1]"),
    ("ndf=phong", "ndf", "ggx"),
    ("g2=magic", "g2", "height_correlated"),
    ("fresnel=exact", "fresnel", "schlick"),
    ("masking=magic", "masking", "smith"),
    ("masking=walter", "masking", "beckmann, blinn_phong only"),
    ("ndf=gtr&alpha_y=0.2", "alpha_y", "isotropic only"),
    ("roughness=0.5&alpha=0.2", "alpha", "not both"),
    ("lambda_phi=ashikhmin", "lambda_phi", "direction_correlated"),
    ("lobe_mix=0.5", "lobe_mix", "alpha2"),
    ("ndf=student_t&gamma=1.5", "gamma", "(1.5, 1000]"),
    ("gamma=3", "gamma", "ndf=gtr or ndf=student_t"),
    ("fresnel=none&f0=0.3", "f0", "fresnel=schlick"),
    ("bogus=1", "bogus", "unknown parameter"),
    ("theta_i_deg=91", "theta_i_deg", "[0, 90]"),
    ("theta_i_deg=-1", "theta_i_deg", "[0, 90]"),
    ("phi_i_deg=nan", "phi_i_deg", "finite"),
    ("theta_i_deg=1,,2", "theta_i_deg", "empty"),
    ("theta_i_deg=1,2&theta_o_deg=1,2,3", "theta_i_deg", "equal length"),
])
def test_eval_rejects_with_named_parameter(client, query, param, needle):
    r = client.get(f"/api/v1/eval?{query}")
    assert r.status_code == 422, r.text
    errors = detail(r)
    assert any(param in e["loc"] for e in errors), errors
    assert any(needle in e["msg"] for e in errors), errors


def test_limits_are_named(small_client):
    cases = [("/api/v1/ndf?n=51", "n", "BRDF_MAX_CURVE_POINTS"),
             ("/api/v1/lobe?n=51", "n", "BRDF_MAX_CURVE_POINTS"),
             ("/api/v1/lobe3d?n_theta=11&n_phi=10", "n_theta×n_phi", "BRDF_MAX_GRID_POINTS"),
             ("/api/v1/albedo?n=6", "n", "BRDF_MAX_ALBEDO_POINTS"),
             ("/api/v1/albedo?mu=0,0.1,0.2,0.3,0.4,0.5", "mu", "BRDF_MAX_ALBEDO_POINTS"),
             ("/api/v1/eval?theta_i_deg=1,2,3,4,5", "theta_i_deg", "BRDF_MAX_QUERY_LIST")]
    for url, param, setting in cases:
        r = small_client.get(url)
        assert r.status_code == 422, (url, r.text)
        (e,) = detail(r)
        assert param in e["loc"] and setting in e["msg"], e


def test_post_batch_over_limit_is_413(small_client):
    r = small_client.post("/api/v1/eval", json={"theta_i_deg": [10.0] * 9, "theta_o_deg": [20.0]})
    assert r.status_code == 413 and "BRDF_MAX_BATCH" in detail(r)[0]["msg"]


def test_empty_lists_are_refused(client):
    r = client.post("/api/v1/eval", json={"theta_i_deg": []})
    assert r.status_code == 422 and "empty" in detail(r)[0]["msg"]


def test_post_rejects_non_finite_numbers(client):
    r = client.post("/api/v1/eval", content='{"theta_i_deg": [NaN]}',
                    headers={"content-type": "application/json"})
    assert r.status_code == 422


def test_every_endpoint_refuses_out_of_range_alpha(client):
    for view in ["ndf", "g1", "lobe", "lobe3d", "albedo", "figures/lobe", "figures/albedo"]:
        r = client.get(f"/api/v1/{view}?alpha=0")
        assert r.status_code == 422 and "alpha" in detail(r)[0]["loc"], (view, r.text)


# ------------------------------------------------------ one mapping for every layer

def _app_raising(exc):
    """The real app with one extra route that raises ``exc`` (as any layer may)."""
    from app.main import create_app
    from tests.budget import settings_for_tests

    app = create_app(settings_for_tests())

    @app.get("/test/raise")
    def raise_it():
        raise exc
    return app


def test_busy_is_503_with_retry_after():
    from fastapi.testclient import TestClient
    from app.errors import Busy

    client = TestClient(_app_raising(Busy("the E(μ, α) table is being built", retry_after=7,
                                          what="table")))
    r = client.get("/test/raise")
    assert r.status_code == 503 and r.headers["retry-after"] == "7"
    (e,) = detail(r)
    assert "being built" in e["msg"] and e["loc"] == ["query", "table"] and e["type"] == "busy"
    assert r.headers["cache-control"] == "no-store"


def test_parameter_error_from_any_layer_is_its_status():
    from fastapi.testclient import TestClient
    from app.errors import ParameterError, TooLarge

    r = TestClient(_app_raising(ParameterError("alpha", "alpha: out of range"))).get(
        "/test/raise")
    assert r.status_code == 422 and detail(r)[0]["loc"] == ["query", "alpha"]
    r = TestClient(_app_raising(TooLarge("n", "n: above BRDF_MAX_CURVE_POINTS"))).get(
        "/test/raise")
    assert r.status_code == 413 and "n" in detail(r)[0]["loc"]


def test_a_failing_error_handler_keeps_the_errors_status(monkeypatch):
    """An exception inside a handler (here: its encoder) is not a 500: the status the
    error asked for, with a generic body."""
    from fastapi.testclient import TestClient
    from app.api import errors
    from app.errors import Busy, ParameterError

    def broken(*args, **kwargs):
        raise RuntimeError("encoder broke")

    monkeypatch.setattr(errors, "_respond", broken)
    client = TestClient(_app_raising(ParameterError("alpha", "bad")), raise_server_exceptions=False)
    assert client.get("/test/raise").status_code == 422
    client = TestClient(_app_raising(Busy("busy")), raise_server_exceptions=False)
    assert client.get("/test/raise").status_code == 503
    r = TestClient(_app_raising(ParameterError("alpha", "bad"))).get("/api/v1/eval?alpha=2",)
    assert r.status_code == 422
