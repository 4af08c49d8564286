"""GET /api/v1/datasets/{id}/figures/{view} and /datasets/{id}/{view}: the data on a
view beside the model, the difference one toggle away, a 4xx for data a view cannot show."""
import numpy as np
import pytest

from . import known

MODEL = known.model("r")


@pytest.fixture(scope="module")
def merl_id(client):
    return client.post("/api/v1/datasets", content=known.merl_bytes()).json()["id"]


@pytest.mark.parametrize("view, kind", [("lobe", "scatterpolar"), ("lobe3d", "surface"),
                                        ("albedo", "scatter"), ("slice", "heatmap"), ("sphere", "heatmap")])
def test_the_data_beside_its_model(client, merl_id, view, kind):
    figure = client.get(f"/api/v1/datasets/{merl_id}/figures/{view}", params={**MODEL, "channel": "r"})
    assert figure.status_code == 200, figure.text
    traces = figure.json()["data"]
    assert "largest" in figure.json()["layout"]["title"]["text"]
    if kind != "heatmap":
        assert traces[-1]["name"] == "data (r)" and traces[-1]["type"] == kind
    difference = client.get(f"/api/v1/datasets/{merl_id}/figures/{view}",
                            params={**MODEL, "channel": "r", "difference": "true"})
    assert difference.status_code == 200
    assert difference.json()["data"][0]["type"] in ("scatter", "heatmap")


def test_the_arrays_and_the_largest_error(client, merl_id):
    out = client.get(f"/api/v1/datasets/{merl_id}/lobe", params={**MODEL, "channel": "r",
                                                                "theta_i_deg": 30}).json()
    error = np.array([np.nan if x is None else x for x in out["relative_error"]])
    inside = np.abs(np.array(out["axes"]["theta_o_deg"])) < 70
    assert np.nanmax(np.abs(error[inside])) < 0.01      # linear interpolation of 1° cells
    assert set(out["where"]) == {"theta_o_deg"}


def test_views_refuse_data_they_cannot_show(client, merl_id):
    ndf = client.get(f"/api/v1/datasets/{merl_id}/figures/ndf", params=MODEL)
    assert ndf.status_code == 422 and ndf.json()["detail"][0]["loc"][-1] == "data"
    assert "term CSV with D" in ndf.json()["detail"][0]["msg"]
    samples = client.post("/api/v1/datasets", content=b"theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n"
                                                       b"30,0,30,180,1\n").json()["id"]
    refused = client.get(f"/api/v1/datasets/{samples}/figures/slice", params=MODEL)
    assert refused.status_code == 422 and "MERL table" in refused.json()["detail"][0]["msg"]
    assert client.get("/api/v1/datasets/" + "0" * 32 + "/figures/lobe").status_code == 404
