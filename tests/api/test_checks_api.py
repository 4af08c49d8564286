"""GET /api/v1/checks and its figure: shape, errors, finite JSON, a table trace."""
from __future__ import annotations

import pytest
from tests.finite import finite_json

ROWS = ["1", "2", "3", "4", "7", "7-loss", "7-furnace"]
COLUMNS = ["id", "identity", "relation", "value", "expected", "error", "difference", "holds",
           "note", "evaluations"]


def test_checks_shape_and_defaults(client):
    r = client.get("/api/v1/checks")
    assert r.status_code == 200, r.text
    body = finite_json(r.content)      # no NaN / Infinity
    assert body["id"] == ROWS
    for key in COLUMNS:
        assert len(body[key]) == len(ROWS), key
    assert body["theta_deg"] == 60.0 and body["phi_deg"] == 0.0
    assert body["mu"] == pytest.approx(0.5)
    assert set(body["seconds_by_row"]) == set(ROWS)
    assert body["total_evaluations"] == sum(body["evaluations"]) > 0
    assert body["complete"] is True
    # default GGX α = 0.3 with exact Smith: rows 1–4 hold; the furnace is not computed
    # (the default model has multiscatter=none) and says so
    assert body["holds"][:4] == [True] * 4
    assert body["holds"][-1] is None and body["value"][-1] is None
    assert "multiscatter=kulla_conty" in body["note"][-1]


def test_ids_select_rows_and_theta_sets_v(client):
    body = client.get("/api/v1/checks?ids=4,2&theta_deg=30").json()
    assert body["id"] == ["2", "4"]
    assert body["expected"][0] == pytest.approx(3 ** 0.5 / 2)      # n·v at 30°


def test_no_nan_in_json_for_a_failing_and_a_grazing_model(client):
    for q in ("ndf=beckmann&masking=walter&alpha=1&theta_deg=89.9",
              "ndf=ggx&masking=schlick_direct&alpha=1e-4&alpha_y=1&phi_deg=-45"):
        r = client.get(f"/api/v1/checks?{q}")
        assert r.status_code == 200, r.text
        finite_json(r.content)


@pytest.mark.parametrize("query, param", [
    ("theta_deg=90", "theta_deg"), ("theta_deg=-1", "theta_deg"), ("theta_deg=abc", "theta_deg"),
    ("phi_deg=400", "phi_deg"), ("ids=5", "ids"), ("ids=", "ids"), ("alpha=0", "alpha")])
def test_bad_queries_are_422_naming_the_parameter(client, query, param):
    r = client.get(f"/api/v1/checks?{query}")
    assert r.status_code == 422, r.text
    assert param in r.json()["detail"][0]["loc"]


def test_figure_is_a_table_naming_the_model(client):
    r = client.get("/api/v1/figures/checks?ndf=beckmann&alpha=0.2")
    assert r.status_code == 200, r.text
    fig = r.json()
    assert [t["type"] for t in fig["data"]] == ["table"]
    header = [h.replace("<b>", "").replace("</b>", "") for h in fig["data"][0]["header"]["values"]]
    assert header == ["identity", "value", "expected", "difference", "error", "holds"]
    assert fig["data"][0]["cells"]["values"][5][:4] == ["✓"] * 4
    assert "Beckmann" in fig["layout"]["title"]["text"]


def test_csv_names_the_rows(client):
    text = client.get("/api/v1/figures/checks.csv?ids=1,3").text
    assert "# row_order = 1, 3" in text
    lines = [line for line in text.splitlines() if not line.startswith("#")]
    header = lines[0].split(",")
    assert header[:2] == ["id", "identity"] and {"value", "expected"} <= set(header)
    assert [line.split(",")[0] for line in lines[1:]] == ["1", "3"]
