"""POST /api/v1/fit: the answer's shape, the fitted model fed back to other endpoints,
and a 4xx naming the field for each bad request."""
import pytest

from tests.datasets import known


@pytest.fixture(scope="module")
def merl_id(client):
    response = client.post("/api/v1/datasets", content=known.merl_bytes())
    assert response.status_code == 201
    return response.json()["id"]


def test_fit_answers_params_errors_and_a_model_any_endpoint_takes(client, merl_id):
    response = client.post("/api/v1/fit", json={
        "data": merl_id, "model": {"ndf": "ggx", "alpha": 0.5, "f0": 0.5, "kd": 0.5},
        "free": ["alpha", "f0", "kd"], "measure": "log", "channel": "r"})
    assert response.status_code == 200, response.text
    out = response.json()
    assert abs(out["params"]["alpha"] / known.ALPHA - 1) < 0.01
    assert abs(out["params"]["f0"] / known.F0["r"] - 1) < 0.02
    assert set(out["stderr"]) == {"alpha", "f0", "kd"}
    assert out["evaluations"] > 3 and 0 < out["seconds"] < 60 and out["converged"]
    assert "fixed-seed random subset" in out["points"]["note"]
    for path in ("/api/v1/lobe", "/api/v1/figures/albedo", "/api/v1/export/model.csv"):
        assert client.get(path, params=out["model"]).status_code == 200, path
    difference = client.get(f"/api/v1/datasets/{merl_id}/difference",
                            params={**out["model"], "channel": "r"}).json()
    assert abs(difference["max_relative_error"]) < 1e-6


def test_fit_all_ranks_every_ndf(client, merl_id):
    response = client.post("/api/v1/fit", json={
        "data": merl_id, "model": {"alpha": 0.5, "f0": 0.5, "kd": 0.5}, "free": ["alpha", "f0", "kd"],
        "fit_all": True, "max_points": 2000, "seconds": 60})
    assert response.status_code == 200, response.text
    ranking = response.json()["ranking"]
    assert {item["ndf"] for item in ranking} | {s["ndf"] for s in response.json()["skipped"]} >= {
        "ggx", "beckmann", "blinn_phong"}
    assert ranking[0]["residual"] <= ranking[-1]["residual"]


@pytest.mark.parametrize("body, status, field", [
    ({"free": ["beta"]}, 422, "free"),
    ({"free": []}, 422, "free"),
    ({"free": ["alpha"], "measure": "squared"}, 422, "measure"),
    ({"free": ["alpha"], "model": {"alpha": 2}}, 422, "model.alpha"),
    ({"free": ["alpha"], "channel": "x"}, 422, "channel"),
    ({"free": ["alpha"], "seconds": 0}, 422, "seconds"),
    ({"free": ["alpha"], "data": "0" * 32}, 404, "data"),
    ({"free": ["alpha"], "data": "zz"}, 422, "data"),
    ({"free": ["alpha"], "extra": 1}, 422, "extra"),
])
def test_bad_fit_requests_name_the_field(client, merl_id, body, status, field):
    response = client.post("/api/v1/fit", json={"data": merl_id, **body})
    assert response.status_code == status, response.text
    assert field in str(response.json()["detail"][0]["loc"]), response.json()
