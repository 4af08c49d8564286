"""MERL tables with unmeasured regions: summarised, never a 500; the view directions
with nothing measured are named and their E is null (issue 34)."""
from __future__ import annotations

import struct

import numpy as np
import pytest

from app.datasets import merl
from tests.datasets.conftest import app, client  # noqa: F401  (fixtures)


def _merl(table: np.ndarray) -> bytes:
    return struct.pack("<3i", *merl.DIMS) + table.astype("<f8").tobytes()


def _upload(client, table):
    res = client.post("/api/v1/datasets", content=_merl(table))
    assert res.status_code == 201, res.text
    return res.json()["summary"]


def test_a_table_whose_every_cell_is_unmeasured_is_summarised(client):
    info = _upload(client, -np.ones((3, *merl.DIMS)))
    albedo = info["albedo"]
    assert info["fraction_measured"] == 0.0
    assert albedo["E"]["r"] == [None] * len(albedo["mu"])
    assert albedo["unmeasured"]["mu"] == albedo["mu"]


def test_a_table_measured_up_to_80_degrees_names_the_grazing_views(client):
    """θ_d ≤ 80° measured (f = 1500 × the channel's scale), beyond it −1: the grazing
    views are partly measured; E is a number with its error, or null (with its error) —
    never a 500, and the coverage says how much was measured."""
    table = np.ones((3, *merl.DIMS)) * 1500.0
    theta_d = (np.arange(merl.DIMS[1]) + 0.5)
    table[:, :, theta_d > 80, :] = -1.0
    info = _upload(client, table)
    albedo = info["albedo"]
    for c in "rgb":
        for E, err, cover in zip(albedo["E"][c], albedo["E_error"][c], albedo["coverage"]):
            assert (E is None) == (err is None)
            if E is not None:
                assert cover < 1 or E > 0
    assert min(albedo["coverage"]) < 1.0          # the grazing views are only partly measured
    # the error covers the unmeasured share: E + E_error ≥ the value the table would give
    # if the missing cells held the measured value (f = 1 everywhere: E = π · 1)
    k = albedo["mu"].index(0.1)
    if albedo["E"]["r"][k] is not None:
        assert albedo["E"]["r"][k] + albedo["E_error"]["r"][k] >= np.pi * 1.0 - 1e-9
