"""Images cannot hide what they show (issue 34): a divergence or a spike covering a
sliver of the image never sets the colour scale; the scale's top and what lies above it
are stated; divergent values are null in the JSON."""
from __future__ import annotations

import base64
import math
import warnings

import numpy as np
import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.main import create_app
from tests.budget import settings_for_tests


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app(settings_for_tests()))


def nan_of(values):
    """A 2-D array from figure JSON: nested lists with nulls, or Plotly's typed array."""
    if isinstance(values, dict) and "bdata" in values:
        a = np.frombuffer(base64.b64decode(values["bdata"]), dtype=values["dtype"]).astype(float)
        shape = values.get("shape")
        return a.reshape([int(k) for k in str(shape).split(",")]) if shape else a
    return np.array(values, dtype=object).astype(float)    # None → nan


def figure(client, view, **params):
    r = client.get(f"/api/v1/figures/{view}", params=params)
    assert r.status_code == 200, r.text
    return r.json()


def test_slice_at_the_default_alpha_shows_the_highlight(client):
    # α = 0.3: f at the highlight (θ_h = 0, θ_d = 30°, GGX, Schlick F0 = 0.04 default) is
    # of order D(0)·F·G/(4 cos²θ_d) with D(0) = 1/(π α²) ≈ 3.5 — far below the 1e12 of the
    # grazing divergence at θ_h = 90°. The colour scale's top must be within two decades
    # of the values at θ_h ≤ 60° (where the image's structure is), not ten above.
    fig = figure(client, "slice", alpha=0.3)
    trace = fig["data"][0]
    f = nan_of(trace["customdata"])
    theta_h = nan_of(trace["x"])
    structure = np.nanmax(f[:, theta_h <= 60.0])
    assert trace["zmax"] <= math.log10(structure) + 2.0
    # and the scale covers those values: the bulk is not all drawn at the floor
    inside = f[:, theta_h <= 60.0]
    inside = inside[np.isfinite(inside) & (inside > 0)]
    assert np.mean(np.log10(inside) > trace["zmin"]) > 0.9


def test_slice_data_has_no_node_at_a_sliver_of_the_divergence(client):
    body = client.get("/api/v1/slice", params={"alpha": 0.3}).json()
    f = nan_of(body["f"])
    # the divergence (both directions graze, θ_h = 90° at φ_d = 90°) is null, and no
    # finite value stands in for it at 1e12
    assert np.nanmax(f) < 1e6
    assert body["peak"]["f_true_max"] < 1e6


def test_slice_colour_bar_states_what_is_clipped(client):
    trace = figure(client, "slice", alpha=0.3)["data"][0]
    title = trace["colorbar"]["title"]["text"]
    assert "percentile" in title or "pct" in title
    assert "%" in title


def test_principled_sphere_with_a_clearcoat_glint_is_not_set_by_it(client):
    # clearcoat = 1, gloss = 1: a GTR1 glint of α = 0.001, a few pixels, far brighter than
    # the rest. The linear scale's top must let the lit half of the sphere read: most lit
    # pixels are drawn above a tenth of the scale.
    fig = figure(client, "sphere", model="principled", clearcoat=1, clearcoat_gloss=1,
                 display="heatmap", n=128)
    trace = fig["data"][0]
    L = nan_of(trace["customdata"])
    lit = L[np.isfinite(L) & (L > 0)]
    assert trace["zmax"] < lit.max()            # the glint does not set it
    assert np.mean(lit > 0.1 * trace["zmax"]) > 0.5
    assert "%" in trace["colorbar"]["title"]["text"]


def test_lobe3d_has_a_colour_bar_set_by_the_bulk(client):
    fig = figure(client, "lobe3d", alpha=0.3, theta_i_deg=89.0)
    surface = fig["data"][0]
    assert surface["showscale"] is True
    assert surface["colorbar"]["title"]["text"]
    f = nan_of(surface["surfacecolor"])
    assert surface["cmax"] <= np.nanmax(f)


def test_every_image_answer_is_null_where_f_diverges(client):
    # GGX at θ_i = 90° and θ_v = 90° in the mirror direction: both graze, f = ∞
    body = client.get("/api/v1/lobe3d", params={"alpha": 0.3, "theta_i_deg": 90.0,
                                                "n_theta": 9, "n_phi": 9}).text
    assert "Infinity" not in body and "NaN" not in body
