"""What each view declares of itself for clients (the page builds its panels from it):
every field described, and the heavy / overlayable / layout flags true to what the view
does — overlayable checked against the figure the view draws (only curve figures can be
overlaid: app/figures/overlay.py); a heavy view is an image or a cloud of samples."""
from __future__ import annotations

import pytest

from app.config import Settings
from app.figures.overlay import overlayable
from app.views import VIEWS, run
from app.views.view import LAYOUTS

#: queries that keep the slow views cheap here (the figure's kind does not depend on them)
CHEAP = {"tradeoff": {"max_budget": 256}, "advise": {"alpha_min": 0.5, "tol": 0.01},
         "samples": {"n": 64}, "sphere": {"n": 16}, "sphere_env": {"n": 16}}


@pytest.mark.parametrize("name", list(VIEWS))
def test_every_field_of_a_view_says_what_it_is(client, name):
    view = next(v for v in client.get("/api/v1/views").json() if v["name"] == name)
    undescribed = [f["name"] for f in view["fields"] if not f["description"].strip()]
    assert undescribed == []


@pytest.mark.parametrize("name", list(VIEWS))
def test_a_views_declared_flags_are_what_it_draws(name):
    view = VIEWS[name]
    declared = view.declared()
    assert {"heavy", "overlayable", "layout", "material"} <= set(declared) <= {"heavy", "overlayable", "layout", "material", "material_refused"}
    assert declared["layout"] in LAYOUTS
    q = view.figure_query.model_validate(CHEAP.get(name, {}))
    result = run(view, q, Settings())
    figure = view.figure(result.data, result.spec, q)
    assert declared["overlayable"] == overlayable(figure)
    if declared["heavy"]:      # an image or a cloud of samples, fetched coarser: never a curve figure
        assert not overlayable(figure)


def test_declaring_an_unknown_layout_is_refused():
    from dataclasses import replace
    with pytest.raises(ValueError, match="layout"):
        replace(VIEWS["lobe"], layout="huge")
