"""POST /api/v1/lut/check names the conventions of Schlick-GGX tables that this test
builds itself by an independent quadrature (reference_split_sum.py, not app/): every
combination of α mapping × G2 form × texel placement × axis order, each stored with one
of the other variations (split form, flips, swapped channels, PNG / 0–255 storage)."""
from __future__ import annotations

import itertools
import json
from functools import lru_cache

import numpy as np
import pytest

from app.lut import png
from tests.lut.reference_split_sum import split_sum_integrals

N = 16
#: what a generator does at the texels on the edge of the domain (r = 0, μ = 0)
GENERATOR_FLOOR = 1e-3
QUERY = "masking=schlick_ibl&ndf=ggx"
COMBOS = list(itertools.product(("alpha = r^2", "alpha = r"), ("separable", "height_correlated"),
                                ("centres", "edges"), ("rows roughness", "rows mu")))


def positions(placement: str) -> np.ndarray:
    return (np.arange(N) + 0.5) / N if placement == "centres" else np.arange(N) / (N - 1.0)


@lru_cache(maxsize=None)
def integrals(alpha_map: str, g2: str, placement: str) -> np.ndarray:
    """[roughness][μ][E₁, E_S] on the generator's grid, by the test's own quadrature."""
    x = positions(placement)
    alphas = np.maximum(x * x if alpha_map == "alpha = r^2" else x, GENERATOR_FLOOR)
    mus = np.maximum(x, GENERATOR_FLOOR)
    return np.array([np.stack(split_sum_integrals(a, mus, g2), axis=-1) for a in alphas])


def stored(e: np.ndarray, case: int, axis_order: str):
    """The table as the variation ``case`` stores it, and the conventions that implies."""
    split = ("split_sum", "dfg_filament")[case % 2]
    e1, es = e[..., 0], e[..., 1]
    t = np.stack([e1 - es, es] if split == "split_sum" else [es, e1], axis=-1)
    flip_r, flip_m, swap = case % 3 == 1, case % 5 == 2, case % 7 == 3
    t = t[::-1] if flip_r else t
    t = t[:, ::-1] if flip_m else t
    t = t[..., ::-1] if swap else t
    if axis_order == "rows mu":
        t = t.transpose(1, 0, 2)
    expect = {"split_form": split, "channels": "swapped" if swap else "as named",
              "roughness_direction": "decreasing" if flip_r else "increasing with the index",
              "mu_direction": "decreasing" if flip_m else "increasing with the index"}
    return t, expect


def upload(client, table: np.ndarray, case: int, kind: str):
    form = case % 4
    if form == 3:                               # a 16-bit PNG, RG in an RGB image
        grid = np.round(np.clip(table, 0, 1) * 65535).astype(np.int64)
        grid = np.concatenate([grid, np.zeros(grid.shape[:-1] + (1,), np.int64)], axis=-1)
        body, ctype, storage = png.write(grid, 16), "image/png", "PNG unorm16"
    elif form == 2:                             # 8-bit integers written as JSON numbers
        body = json.dumps({"values": np.round(table * 255).tolist()}).encode()
        ctype, storage = "application/json", "0–255"
    else:
        body, ctype, storage = json.dumps({"values": table.tolist()}).encode(), "application/json", "unit floats"
    res = client.post(f"/api/v1/lut/check?kind={kind}&{QUERY}", content=body, headers={"content-type": ctype})
    assert res.status_code == 200, res.text
    return res.json(), storage, form


@pytest.mark.parametrize("case, combo", list(enumerate(COMBOS)), ids=["|".join(c) for c in COMBOS])
def test_check_names_every_convention(client, case, combo):
    alpha_map, g2, placement, axis_order = combo
    table, expect = stored(integrals(alpha_map, g2, placement), case, axis_order)
    expect.update({"alpha_mapping": alpha_map, "g2": g2, "roughness_texels": placement, "mu_texels": placement,
                   "axis_order": axis_order, "mu_mapping": "mu = x"})
    out, storage, form = upload(client, table, case, "split_sum")
    found = out["conventions"]
    assert {k: found[k] for k in expect} == expect, out["fit"]
    assert storage in out["storage"]
    # the residual is the quadratures' difference (~1e-5) plus the storage's rounding
    step = {2: 1 / 255, 3: 1 / 65535}.get(form, 0.0)
    assert out["fit"]["residual_rms"] < 1e-4 + 0.5 * step, out["fit"]
    # every convention decided by a clear margin over its best alternative
    for name, m in out["fit"]["margins"].items():
        assert m["ratio"] is None or m["ratio"] > 3, (name, m)
    # what differs from the query is named, and nothing else
    query_side = {"split_form": "split_sum", "alpha_mapping": "alpha = r^2", "roughness_texels": "centres",
                  "mu_texels": "centres", "axis_order": "rows roughness", "channels": "as named",
                  "roughness_direction": "increasing with the index", "mu_direction": "increasing with the index"}
    named = {k for k in out["differs"] if k not in ("g2", "storage")}
    assert named == {k for k, v in query_side.items() if expect[k] != v}
    # the error map after bilinear filtering, in the inferred (canonical) arrangement: at a
    # middle texel, the max over its centre and the half-texel points, each recomputed
    # here with the test's own quadrature, against the mean of the neighbouring texels
    err = np.array(out["error"]["per_texel"])
    assert err.shape == (N, N, 2) and out["error"]["indices"] == list(range(N))
    i = j = N // 2
    e = integrals(alpha_map, g2, placement)
    canon = np.stack([e[..., 0] - e[..., 1], e[..., 1]] if expect["split_form"] == "split_sum"
                     else [e[..., 1], e[..., 0]], axis=-1)
    x = positions(placement)
    worst = np.zeros(2)
    for di, dj in ((0, 0), (1, 0), (0, 1), (1, 1)):
        xr, xm = x[i] + di * (x[i + 1] - x[i]) / 2, x[j] + dj * (x[j + 1] - x[j]) / 2
        e1, es = split_sum_integrals(xr * xr if alpha_map == "alpha = r^2" else xr, np.array([xm]), g2)
        want = np.array([e1[0] - es[0], es[0]] if expect["split_form"] == "split_sum" else [es[0], e1[0]])
        got = np.mean([canon[r, c] for r in {i, i + di} for c in {j, j + dj}], axis=0)
        worst = np.maximum(worst, np.abs(got - want))
    assert np.allclose(err[i, j], worst, atol=2e-4 + step), (err[i, j], worst)
