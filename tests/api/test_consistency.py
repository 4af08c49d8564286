"""The API answers alike wherever it can: POST broadcasts as GET does, ``vary`` works on
every figure route, unknown names are 404s that list the valid ones, a cached answer
says so, and every table names its rows."""
from __future__ import annotations

import csv
import io

import pytest

from app.views import ROLES, VIEWS


def test_post_eval_broadcasts_a_scalar_as_get_does(client):
    get = client.get("/api/v1/eval?theta_i_deg=30&theta_o_deg=10,20&phi_o_deg=180&quantities=f")
    post = client.post("/api/v1/eval", json={"theta_i_deg": 30, "theta_o_deg": [10, 20],
                                             "phi_o_deg": 180, "quantities": "f"})
    assert get.status_code == 200 and post.status_code == 200, post.text
    assert post.json() == get.json() and len(post.json()["f"]) == 2


@pytest.mark.parametrize("path", ["/api/v1/figures/ndf", "/api/v1/figures/ndf.json"])
def test_vary_works_on_every_figure_route(client, path):
    r = client.get(f"{path}?vary=ndf&values=ggx,beckmann&alpha=0.3")
    assert r.status_code == 200, r.text
    names = " ".join(t.get("name", "") for t in r.json()["data"])
    assert "ndf=ggx" in names and "ndf=beckmann" in names


def test_the_figure_and_its_json_export_are_one_route(client):
    a = client.get("/api/v1/figures/lobe?vary=alpha&values=0.1,0.4")
    b = client.get("/api/v1/figures/lobe.json?vary=alpha&values=0.1,0.4")
    assert a.status_code == b.status_code == 200 and a.content == b.content


@pytest.mark.parametrize("path, listed", [
    ("/api/v1/figures/no_such_view", "ndf"),
    ("/api/v1/figures/no_such_view.svg", "lobe"),
    ("/api/v1/figures/ndf.bmp", "svg, png, csv, json"),
    ("/api/v1/no_such_view", "albedo"),
    ("/embed/no_such_view", "sphere"),
])
def test_unknown_views_and_formats_are_404s_that_list_the_valid_ones(client, path, listed):
    r = client.get(path)
    assert r.status_code == 404, r.text
    (e,) = r.json()["detail"]
    assert listed in e["msg"], e


def test_a_known_path_with_another_method_stays_405(client):
    assert client.post("/api/v1/figures/ndf.svg").status_code == 405
    assert client.post("/api/v1/ndf").status_code == 405


def test_a_cached_albedo_says_it_was_cached(client):
    url = "/api/v1/albedo?mu=0.3,0.7&alpha=0.41&fresnel=none"      # used by no other test
    first = client.get(url).json()
    again = client.get(url).json()
    assert first["cached"] is False and first["seconds"] > 0
    assert first["computed_seconds"] == first["seconds"]
    assert again["cached"] is True and again["seconds"] == 0.0
    assert again["computed_seconds"] == first["seconds"] and again["E"] == first["E"]


def _columns(client, url: str) -> dict[str, list[str]]:
    """The CSV's columns by header name (comment lines skipped, as pandas' comment="#")."""
    r = client.get(url)
    assert r.status_code == 200, r.text
    lines = [line for line in r.text.splitlines() if not line.startswith("#")]
    rows = list(csv.reader(io.StringIO("\n".join(lines))))
    return {name: [row[i] for row in rows[1:]] for i, name in enumerate(rows[0])}


def test_the_checks_csv_names_its_rows(client):
    table = _columns(client, "/api/v1/figures/checks.csv?ids=1,3,7")
    assert table["id"] == ["1", "3", "7"]
    assert all("D" in text or "E" in text for text in table["identity"])


def test_the_advise_csv_names_its_rows(client):
    table = _columns(client, "/api/v1/figures/advise.csv?alpha_min=0.2&alpha_max=0.5&theta_max_deg=60")
    assert table["label"][0] == "current model"
    assert len(table["label"]) == len(set(table["label"])) > 1


def test_views_list_titles_and_field_roles(client):
    views = client.get("/api/v1/views").json()
    assert [v["name"] for v in views] == list(VIEWS)
    for v in views:
        assert v["title"] and v["summary"] and v["embed"] == f"/embed/{v['name']}"
        for f in v["fields"]:
            assert f["role"] in ROLES, (v["name"], f)
