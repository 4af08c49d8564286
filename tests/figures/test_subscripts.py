"""Indexed symbols read as the physics writes them: Plotly shows "θ_v" with its underscore,
so every figure writes Plotly's subscript markup, "θ<sub>v</sub>" (issue 11), in its title,
axis and colourbar titles, legend names, annotations, hover templates and table cells.

A symbol is one letter standing alone; a word of several letters with an underscore is an
API name ("theta_o_deg", "alpha_y=0.5", "mc_uniform", "height_correlated") and stays as
the API spells it. Data keys and CSV columns are API names too: they do not change."""
import re
import warnings

import pytest

from app.figures.markup import markup, subscripts
from tests.budget import settings_for_tests

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.main import create_app

#: a symbol letter (not the end of a longer word: that is an API name), "_", an index
RAW_INDEX = re.compile(r"(?<![\w])[A-Za-zα-ωΑ-Ω]_[A-Za-z0-9]")
#: keys whose string values a reader sees
TEXT_KEYS = {"text", "name", "hovertemplate", "title"}


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(settings_for_tests()))


def texts(node, path=""):
    """(path, text) of every text a reader sees in a figure (or part of one)."""
    if isinstance(node, dict):
        for key, value in node.items():
            where = f"{path}.{key}" if path else key
            if isinstance(value, str) and key in TEXT_KEYS:
                yield where, value
            elif key == "values" and path.endswith(("cells", "header")):
                yield from ((f"{where}[]", v) for v in _flat(value) if isinstance(v, str))
            elif isinstance(value, (dict, list)) and key not in ("meta", "customdata"):
                yield from texts(value, where)
    elif isinstance(node, list):
        for k, value in enumerate(node):
            if isinstance(value, (dict, list)):
                yield from texts(value, f"{path}[{k}]")


def _flat(values):
    for v in values if isinstance(values, list) else [values]:
        yield from _flat(v) if isinstance(v, list) else [v]


def test_no_figure_of_any_view_shows_a_raw_underscore_index(client):
    views = [v["name"] for v in client.get("/api/v1/views").json()]
    assert len(views) >= 10
    raw = []
    for name in views:
        r = client.get(f"/api/v1/figures/{name}")
        assert r.status_code == 200, (name, r.text[:300])
        raw += [(name, where, text) for where, text in texts(r.json()) if RAW_INDEX.search(text)]
    assert raw == [], "\n".join(f"{n} {w}: {t[:120]}" for n, w, t in raw)


@pytest.mark.parametrize("view, where, shown", [
    ("ndf", ("layout", "xaxis", "title", "text"), "θ<sub>m</sub> (degrees)"),
    ("g1", ("layout", "xaxis", "title", "text"), "θ<sub>v</sub> (degrees)"),
    ("albedo", ("layout", "xaxis", "title", "text"), "μ = cos θ<sub>v</sub>"),
    ("principled_albedo", ("layout", "xaxis", "title", "text"), "θ<sub>v</sub> (deg)"),
])
def test_symbols_are_written_as_plotly_subscripts(client, view, where, shown):
    node = client.get(f"/api/v1/figures/{view}").json()
    for key in where:
        node = node[key]
    assert node == shown


def test_api_names_and_data_keys_stay_as_the_api_spells_them(client):
    fig = client.get("/api/v1/figures/ndf", params={"vary": "alpha_y", "values": "0.1,0.3"}).json()
    assert [t["name"] for t in fig["data"]] == ["alpha_y=0.1", "alpha_y=0.3"]
    assert "D(θ<sub>m</sub>)" in fig["layout"]["title"]["text"]
    lobe = client.get("/api/v1/lobe").json()
    assert "theta_o_deg" in lobe
    header = client.get("/api/v1/figures/lobe.csv").text.splitlines()
    assert any(line.startswith("theta_o_deg") for line in header), header[:12]


def test_exported_images_are_drawn_from_the_marked_figure():
    """SVG and PNG are rendered (kaleido) from the figure the view's pipeline builds, not
    from the JSON: that figure carries the markup, for every view (the principled albedo's
    builder lives outside app/figures)."""
    from app.views import VIEWS, run
    settings = settings_for_tests()
    raw = []
    for name, view in VIEWS.items():
        fig = run(view, view.figure_query(), settings).figure()
        raw += [(name, where, text) for where, text in texts(fig) if RAW_INDEX.search(text)]
    assert raw == [], raw
    view = VIEWS["g1"]
    figure = run(view, view.figure_query(), settings).figure()
    assert figure["layout"]["xaxis"]["title"]["text"] == "θ<sub>v</sub> (degrees)"
    assert [t["name"] for t in figure["data"]][:2] == ["G1(θ<sub>v</sub>)", "Λ(θ<sub>v</sub>) (right axis, log)"]


@pytest.mark.parametrize("given, want", [
    ("θ_v", "θ<sub>v</sub>"),
    ("D(θ_m)·cos θ_m", "D(θ<sub>m</sub>)·cos θ<sub>m</sub>"),
    ("E_avg = 0.04885", "E<sub>avg</sub> = 0.04885"),
    ("G_1, α_x, μ_o, f_r, L_o/E", "G<sub>1</sub>, α<sub>x</sub>, μ<sub>o</sub>, f<sub>r</sub>, L<sub>o</sub>/E"),
    ("θ_o=%{theta:.1f}°<br>%{r:.4g}", "θ<sub>o</sub>=%{theta:.1f}°<br>%{r:.4g}"),
    # API names stay names
    ("theta_o_deg", "theta_o_deg"),
    ("alpha_y=0.5", "alpha_y=0.5"),
    ("mc_uniform: reported error", "mc_uniform: reported error"),
    ("masking=schlick_direct", "masking=schlick_direct"),
    ("θ_o_deg", "θ_o_deg"),
    ("%{customdata_x}", "%{customdata_x}"),
])
def test_subscripts(given, want):
    assert subscripts(given) == want
    assert subscripts(want) == want                      # idempotent


def test_markup_leaves_arrays_and_the_given_figure_alone():
    import numpy as np
    x = np.arange(3.0)
    given = {"data": [{"type": "scatter", "name": "θ_v", "x": x, "legendgroup": "mc_ndf",
                       "marker": {"colorbar": {"title": {"text": "f_r"}}}},
                      {"type": "table", "cells": {"values": [["E_sep", 1.0]]}}],
             "layout": {"title": {"text": "α_x"}, "annotations": [{"text": "k_d"}]}}
    out = markup(given)
    assert out["data"][0]["x"] is x and out["data"][0]["legendgroup"] == "mc_ndf"
    assert out["data"][0]["name"] == "θ<sub>v</sub>"
    assert out["data"][0]["marker"]["colorbar"]["title"]["text"] == "f<sub>r</sub>"
    assert out["data"][1]["cells"]["values"] == [["E<sub>sep</sub>", 1.0]]
    assert out["layout"]["title"]["text"] == "α<sub>x</sub>"
    assert out["layout"]["annotations"][0]["text"] == "k<sub>d</sub>"
    assert given["data"][0]["name"] == "θ_v" and given["layout"]["title"]["text"] == "α_x"
