"""Axes a reader can read, as the figure routes send them (issue 11): the albedo's y axis
fits the data by default (with F0 = 0.04 a fixed 0-1 axis put every curve in its bottom
fifth) and spans 0-1 on request; a log axis over a couple of decades carries more than one
or two labels."""
from __future__ import annotations

import math

import numpy as np


def _figure(client, url: str) -> dict:
    r = client.get(url)
    assert r.status_code == 200, r.text
    return r.json()


def test_albedo_axis_fits_the_data_by_default_and_spans_0_to_1_on_request(client):
    E = np.asarray(_figure(client, "/api/v1/albedo")["E"], dtype=float)
    lo, hi = _figure(client, "/api/v1/figures/albedo")["layout"]["yaxis"]["range"]
    assert lo <= E.min() and hi >= E.max()
    assert (E.max() - E.min()) / (hi - lo) > 0.6, (lo, hi, E.min(), E.max())
    unit = _figure(client, "/api/v1/figures/albedo?y_range=unit")["layout"]["yaxis"]["range"]
    assert unit[0] == 0.0 and unit[1] >= 1.0


def _labels(axis: dict) -> list[float]:
    """The tick values Plotly labels on a log axis with this dtick and range (log10 ends):
    "D1" every digit, "D2" 1, 2 and 5 of each decade, a number every that many decades."""
    lo, hi = axis["range"]
    dtick = axis.get("dtick")
    digits = {"D1": range(1, 10), "D2": (1, 2, 5)}.get(dtick)
    step = 1 if digits else float(dtick)
    out, e = [], math.floor(lo)
    while e <= hi:
        for d in digits or (1,):
            x = math.log10(d) + e
            if lo <= x <= hi:
                out.append(10 ** x)
        e += step
    return out


def test_a_log_axis_over_a_few_decades_has_several_labels(client):
    axis = _figure(client, "/api/v1/figures/ndf?alpha=0.8&log=true")["layout"]["yaxis"]
    assert axis["type"] == "log" and axis["range"][1] - axis["range"][0] < 3
    assert len(_labels(axis)) >= 4, axis
