"""GET /api/v1/advise and its figure: the response shape, the recommendation fed back into
other endpoints, the 422s, finite JSON, the table figure."""
from __future__ import annotations

import pytest

from app.figures.advise import RECOMMENDED_FILL
from app.model import make_spec
from tests.finite import finite_json

#: a narrow scene keeps each request to a few tenths of a second
SCENE = {"alpha_min": 0.1, "alpha_max": 0.4, "theta_max_deg": 70}


def test_response_names_recommendation_error_cost_alternatives(client):
    r = client.get("/api/v1/advise", params={**SCENE, "tol": 0.02})
    assert r.status_code == 200, r.text
    d = finite_json(r.text)
    assert {"recommendation", "max_error", "relative_cost", "alternatives"} <= set(d)
    assert d["complete"] is True
    labels = [e["label"] for e in d["alternatives"]]
    assert "masking=karis" in labels and "g2=separable" in labels
    for e in d["alternatives"]:
        assert e["max_error"] >= 0 and e["relative_cost"] > 0
        assert e["within_tol"] == (e["max_error"] <= 0.02)
    # row 0 of the CSV columns is the current model, then the alternatives in order
    assert d["max_errors"] == [0.0] + [e["max_error"] for e in d["alternatives"]]
    assert len(d["relative_costs"]) == len(d["within_tol"]) == 1 + len(labels)


@pytest.mark.parametrize("model", [{}, {"fresnel": "dielectric", "ior": 1.7, "tol": 0.1},
                                   {"ndf": "beckmann", "roughness": 0.5}])
def test_recommendation_feeds_back_into_other_endpoints(client, model):
    d = client.get("/api/v1/advise", params={**SCENE, **model}).json()
    rec = d["recommendation"]
    make_spec(**rec)
    r = client.get("/api/v1/lobe", params={**rec, "n": 5})
    assert r.status_code == 200, r.text
    for e in d["alternatives"]:
        assert client.get("/api/v1/g1", params={**e["model"], "n": 3}).status_code == 200


@pytest.mark.parametrize("query, param", [
    ({"alpha_min": 0.5, "alpha_max": 0.2}, "alpha_min"),
    ({"tol": 0}, "tol"), ({"tol": 0.9}, "tol"),
    ({"alpha_min": 0}, "alpha_min"), ({"alpha_max": 2}, "alpha_max"),
    ({"theta_max_deg": 91}, "theta_max_deg"), ({"theta_max_deg": -1}, "theta_max_deg"),
    ({"alpha_y": 0.1}, "alpha_y"), ({"roughness": 0.5, "anisotropy": 0.5}, "anisotropy"),
    ({"tol": "nan"}, "tol"), ({"bogus": 1}, "bogus"),
])
def test_bad_queries_are_422_naming_the_parameter(client, query, param):
    r = client.get("/api/v1/advise", params=query)
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"][-1] == param


def test_cut_by_the_budget_says_so(client):
    from app.config import Settings
    from app.main import create_app
    from fastapi.testclient import TestClient
    # a budget its first albedo pass fits (a zero budget refuses all work up front: 413)
    tight = TestClient(create_app(Settings(max_seconds=0.05)))
    r = tight.get("/api/v1/advise", params={**SCENE, "alpha_min": 0.11})
    assert r.status_code == 200
    d = finite_json(r.text)
    assert d["complete"] is False and "BRDF_MAX_SECONDS" in d["note"]
    assert d["recommendation"] == d["current"]


def test_figure_is_a_table_with_the_recommendation_highlighted(client):
    r = client.get("/api/v1/figures/advise", params=SCENE)
    assert r.status_code == 200, r.text
    fig = r.json()
    (table,) = fig["data"]
    assert table["type"] == "table"
    rows = table["cells"]["values"][0]
    d = client.get("/api/v1/advise", params=SCENE).json()
    assert rows[0] == "current model" and len(rows) == 1 + len(d["alternatives"])
    fills = table["cells"]["fill"]["color"][0]
    chosen = 0 if not d["changes"] else 1 + [e["changes"] for e in d["alternatives"]].index(d["changes"])
    assert fills[chosen] == RECOMMENDED_FILL and fills.count(RECOMMENDED_FILL) == 1
    assert "Recommended" in fig["layout"]["title"]["text"]


def test_material_is_refused_before_work_not_a_500(client):
    """advise with a measured material (RGB Fresnel) raised KeyError('ior'): a 500."""
    r = client.get("/api/v1/advise", params={"material": "aluminum", "albedo_methods": "true"})
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"] == ["query", "material"]
    r = client.get("/api/v1/albedo", params={"material": "aluminum", "method": "table"})
    assert r.status_code == 422 and r.json()["detail"][0]["loc"] == ["query", "method"]
