"""vary/values: one curve per value, each the same as a single figure of that value."""
from __future__ import annotations

import json

import pytest


def figure(client, url):
    r = client.get(url)
    assert r.status_code == 200, r.text
    return json.loads(r.text)


def test_one_curve_per_value_equal_to_the_single_figures(client):
    over = figure(client, "/api/v1/figures/ndf.json?alpha=0.3&vary=ndf&values=ggx,beckmann&n=11")
    curves = [t for t in over["data"] if not (t.get("meta") or {}).get("role") == "guide"]
    assert [t["name"] for t in curves] == ["ndf=ggx", "ndf=beckmann"]
    assert curves[0]["line"]["color"] != curves[1]["line"]["color"]
    for name, trace in zip(("ggx", "beckmann"), curves):
        single = figure(client, f"/api/v1/figures/ndf?alpha=0.3&ndf={name}&n=11")
        assert trace["y"] == single["data"][0]["y"]
    assert "ndf = ggx, beckmann" in over["layout"]["title"]["text"]


def test_guides_drawn_once_and_ranges_cover_every_curve(client):
    over = figure(client, "/api/v1/figures/lobe.json?log=true&theta_i_deg=60&vary=alpha&values=0.05,0.5&n=31")
    guides = [t for t in over["data"] if (t.get("meta") or {}).get("role") == "guide"]
    assert sorted(t["name"] for t in guides) == ["incident l", "mirror", "normal n"]
    lo, hi = over["layout"]["polar"]["radialaxis"]["range"]
    for alpha in ("0.05", "0.5"):
        single = figure(client, f"/api/v1/figures/lobe?log=true&theta_i_deg=60&alpha={alpha}&n=31")
        s_lo, s_hi = single["layout"]["polar"]["radialaxis"]["range"]
        assert lo <= s_lo and hi >= s_hi


@pytest.mark.parametrize("url, param", [
    ("/api/v1/figures/sphere.json?n=8&vary=alpha&values=0.1,0.2", "vary"),      # an image
    ("/api/v1/figures/ndf.json?vary=alpha&values=0.1,7", "values"),             # out of range
    ("/api/v1/figures/ndf.json?vary=ndf&values=ggx,nonsense", "values"),
    ("/api/v1/figures/ndf.json?vary=alpha&values=" + ",".join(["0.1"] * 2), "values"),   # repeated
    ("/api/v1/figures/ndf.json?vary=alpha&values=" + ",".join(str(0.1 * k) for k in range(1, 10)), "values"),
    ("/api/v1/figures/ndf.json?values=0.1,0.2", "vary"),                         # no vary
    ("/api/v1/figures/ndf.json?vary=n&values=3,5", "vary"),                      # resolution: not varied
])
def test_bad_overlays_are_422_naming_the_parameter(client, url, param):
    r = client.get(url)
    assert r.status_code == 422, r.text
    assert r.json()["detail"][0]["loc"][-1] == param


def test_overlay_of_traces_holding_arrays_of_different_lengths():
    """Two named curves per figure whose x arrays differ in length: finding a trace's
    place by `trace in named` compared the arrays and raised (a 500)."""
    import numpy as np
    from app.figures.overlay import overlay

    def figure(n):
        return {"data": [{"type": "scatter", "name": "a", "x": np.arange(3), "y": np.arange(3)},
                         {"type": "scatter", "name": "b", "x": np.arange(n), "y": np.arange(n)}],
                "layout": {}}
    merged = overlay([figure(4), figure(5)], ["one", "two"], "title")
    dashes = [t["line"]["dash"] for t in merged["data"]]
    assert len(merged["data"]) == 4 and dashes[0] != dashes[1] and dashes[:2] == dashes[2:]
