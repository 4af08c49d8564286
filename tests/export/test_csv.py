"""CSV exports: columns named with units, the same numbers as the JSON data endpoint
(for every view in VIEWS, including views added later), grids in long format."""
from __future__ import annotations

import math

import numpy as np
import pytest

from app import kernels
from app.views import VIEWS
from app.errors import ParameterError
from app.export import table

from .conftest import read_csv

# Small grids so that every view is quick; a view without these fields takes defaults.
SMALL = {"n": 9, "n_theta": 5, "n_phi": 7}
#: numpy's and the compiled loops' float64 results differ by a few ulp
ULPS = 1e-12


def small_query(kind: str) -> dict:
    fields = VIEWS[kind].figure_query.model_fields
    q = {k: v for k, v in SMALL.items() if k in fields}
    if "n" in q and fields["n"].metadata:
        lo = next((m.ge for m in fields["n"].metadata if getattr(m, "ge", None) is not None), 2)
        q["n"] = max(q["n"], lo)
    return q


def cell(text: str) -> float:
    return math.nan if text == "" else float(text)


def as_float(values) -> np.ndarray:
    return np.array([math.nan if x is None else x for x in np.ravel(np.asarray(values, dtype=object))],
                    dtype=float).reshape(np.shape(values))


@pytest.mark.parametrize("kind", list(VIEWS))
def test_csv_columns_match_the_json(client, kind):
    q = small_query(kind)
    data = client.get(f"/api/v1/{kind}", params=q)
    assert data.status_code == 200, data.text
    data = data.json()
    res = client.get(f"/api/v1/figures/{kind}.csv", params=q)
    assert res.status_code == 200, res.text
    assert res.headers["content-type"].startswith("text/csv")
    comments, header, rows = read_csv(res.text)
    assert comments["view"] == kind
    keys = [table.json_key(c) for c in header]
    arrays = {k: as_float(v) for k, v in data.items()
              if isinstance(v, list) and v and not isinstance(v[0], (dict, str))}
    # lists of texts that name the rows (the checks' id, the advice's label) are columns too,
    # first, with the texts themselves
    labels = {k: v for k, v in data.items() if isinstance(v, list) and len(v) == len(rows)
              and all(isinstance(x, str) for x in v)}
    assert keys[:len(labels)] == list(labels), (header, list(labels))
    for i, k in enumerate(labels):
        assert [r[i] for r in rows] == labels[k]
    keys = keys[len(labels):]
    rows = [r[len(labels):] for r in rows]
    # a colour grid (last axis: r, g, b) is one column per channel; a 3-vector beside
    # it (the background colour) is a comment
    for k, a in list(arrays.items()):
        if a.ndim >= 3 and a.shape[-1] == 3:
            del arrays[k]
            arrays.update({f"{k}_{c}": a[..., i] for i, c in enumerate("rgb")})
    if any(k.endswith("_r") for k in arrays):
        for k in [k for k, a in arrays.items() if a.shape == (3,)]:
            assert [float(x) for x in comments[k].split(",")] == arrays.pop(k).tolist()
    # every array of the payload is a column, named after its key (plus its unit)
    assert set(keys) == set(arrays), (header, list(arrays))
    cols = {k: np.array([cell(r[i]) for r in rows]) for i, k in enumerate(keys)}
    grids = {k: a for k, a in arrays.items() if a.ndim == 2}
    if not grids:
        for k, a in arrays.items():
            # NaN (null) ↔ empty cell, both. Two requests: between them the compiled
            # loops may have become ready (the first answered by numpy), a difference of
            # a few ulp; exact round-tripping is test_numbers_round_trip_exactly's
            np.testing.assert_allclose(cols[k], a, rtol=ULPS, atol=0, equal_nan=True)
        return
    # long format: one row per grid point; the axes are the 1-D arrays in payload order
    shape = next(iter(grids.values())).shape
    axes = [k for k, a in arrays.items() if a.ndim == 1]
    assert len(rows) == shape[0] * shape[1]
    for k, grid in grids.items():
        for r, row in enumerate(rows):
            i, j = divmod(r, shape[1])
            assert cols[axes[0]][r] == arrays[axes[0]][i] and cols[axes[1]][r] == arrays[axes[1]][j]
            expected = grid[i, j]
            assert (math.isnan(expected) and math.isnan(cols[k][r])) or \
                math.isclose(cols[k][r], expected, rel_tol=ULPS, abs_tol=0)


def test_header_names_units(client):
    _, header, _ = read_csv(client.get("/api/v1/figures/ndf.csv").text)
    assert header == ["theta_deg", "D_per_sr"]
    _, header, _ = read_csv(client.get("/api/v1/figures/lobe3d.csv?n_theta=3&n_phi=4").text)
    assert header == ["theta_deg", "phi_deg", "f_per_sr"]
    _, header, _ = read_csv(client.get("/api/v1/figures/lobe.csv?cosine=true&n=5").text)
    assert header == ["theta_o_deg", "f_cos_per_sr"]
    _, header, _ = read_csv(client.get("/api/v1/figures/sphere.csv?n=8").text)
    assert header == ["y", "x", "radiance_per_sr"]


def test_csv_states_the_model_in_comments(client):
    comments, _, _ = read_csv(client.get("/api/v1/figures/ndf.csv?ndf=beckmann&alpha=0.2").text)
    assert comments["ndf"] == "beckmann" and comments["alpha"] == "0.2" and comments["log"] == "true"


def test_divergence_is_an_empty_cell(client):
    # Λ(θ = 90°) = +inf (JSON null): the last row's Λ cell is empty, G1 there is 0
    _, header, rows = read_csv(client.get("/api/v1/figures/g1.csv?n=3").text)
    last = dict(zip(header, rows[-1]))
    assert last["theta_deg"] == "90.0" and last["Lambda"] == "" and float(last["G1"]) == 0.0


def test_numbers_round_trip_exactly(client):
    # repr of a float64 reads back as the same float: the CSV loses nothing (both
    # requests on the numpy path, so that the two computations are the same)
    with kernels.disabled():
        data = client.get("/api/v1/ndf?n=7&alpha=0.123").json()
        _, _, rows = read_csv(client.get("/api/v1/figures/ndf.csv?n=7&alpha=0.123").text)
    assert [float(r[1]) for r in rows] == data["D"]


def test_varied_csv_has_one_block_per_value(client):
    text = client.get("/api/v1/figures/albedo.csv?n=3&vary=alpha&values=0.1,0.5").text
    comments, header, rows = read_csv(text)
    assert header[0] == "alpha" and {"mu", "E", "E_error"} <= set(header)
    assert [r[0] for r in rows] == ["0.1"] * 3 + ["0.5"] * 3
    E = header.index("E")
    for value, block in (("0.1", rows[:3]), ("0.5", rows[3:])):
        single = client.get(f"/api/v1/albedo?n=3&alpha={value}").json()
        assert [float(r[E]) for r in block] == single["E"]
        assert float(comments[f"E_avg [alpha={value}]"]) == single["E_avg"]


def test_varied_csv_with_a_column_only_some_values_have(client):
    # the approximation (walter) has G1_exact and G1_error, exact Smith does not
    text = client.get("/api/v1/figures/g1.csv?ndf=beckmann&n=3&vary=masking&values=smith,walter").text
    _, header, rows = read_csv(text)
    walter = client.get("/api/v1/g1?ndf=beckmann&n=3&masking=walter").json()
    extra = [k for k in walter if k not in ("theta_deg", "Lambda", "G1") and isinstance(walter[k], list)]
    assert extra and set(extra) <= set(header)
    # each model has its own refined angles: split the rows by the varied column
    which = header.index("masking")
    smith = [r for r in rows if r[which] == "smith"]
    walter_rows = [r for r in rows if r[which] == "walter"]
    assert len(smith) + len(walter_rows) == len(rows) and len(walter_rows) == len(walter["G1"])
    for k in extra:
        col = header.index(k)
        assert all(r[col] == "" for r in smith)                               # smith: empty
        assert [float(r[col]) if r[col] else None for r in walter_rows] == walter[k]


def test_table_layout_rules():
    # a wide table, a grid with an axis missing (index column), and payloads that fit neither
    assert list(table.columns({"a": [1, 2], "b": [3, 4], "note": "x"})) == ["a", "b"]
    cols = table.columns({"t": np.array([0.0, 1.0]), "g": np.arange(6.0).reshape(2, 3)})
    assert list(cols) == ["t", "index1", "g"]
    np.testing.assert_array_equal(cols["index1"], [0, 1, 2, 0, 1, 2])
    np.testing.assert_array_equal(cols["g"], np.arange(6.0))
    with pytest.raises(ParameterError):
        table.columns({"a": [1, 2], "b": [1, 2, 3]})
    with pytest.raises(ParameterError):
        table.columns({"x": [1.0, 2.0], "stray": [1.0, 2.0, 3.0, 4.0], "g": np.zeros((2, 2))})
