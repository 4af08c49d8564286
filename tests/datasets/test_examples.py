"""The server's example data set: answered without an upload, and true to its description."""
from __future__ import annotations

import csv
import io

import numpy as np

from app.datasets import examples
from app.datasets.store import DatasetStore


def test_the_example_answers_without_an_upload(app, client):
    """A store that never saw it answers the example's id (read from the file the first
    time, kept in the store after); other ids are 404 as before."""
    app.state.datasets = examples.WithExamples(DatasetStore(max_bytes=1 << 24))
    example_id = examples.example_id("ggx-samples")
    assert example_id not in app.state.datasets
    r = client.get(f"/api/v1/datasets/{example_id}")
    assert r.status_code == 200 and r.json()["format"] == "samples_csv"
    assert example_id in app.state.datasets
    assert client.get("/api/v1/datasets/" + "0" * 32).status_code == 404


def test_the_example_comes_back_after_an_eviction(app, client):
    """A store too small for two: an upload evicts the example, whose id still answers."""
    store = DatasetStore(max_bytes=examples.load("ggx-samples")[0].nbytes + 100)
    app.state.datasets = examples.WithExamples(store)
    example_id = examples.example_id("ggx-samples")
    assert client.get(f"/api/v1/datasets/{example_id}").status_code == 200
    other = b"theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n30,0,30,180,1.5\n45,0,20,90,0.25\n"
    assert client.post("/api/v1/datasets", content=other).status_code == 201
    assert example_id not in store
    assert client.get(f"/api/v1/datasets/{example_id}").status_code == 200


def test_the_example_file_is_what_the_export_writes(client):
    """The shipped CSV is the export of the model its description names, so "written from
    GGX (α = 0.3, …)" stays true if the model's formulas change."""
    example = examples.EXAMPLES["ggx-samples"]
    assert "synthetic" in example.description
    r = client.get("/api/v1/export/model.csv", params={**example.model, **example.grid})
    assert r.status_code == 200

    def rows(text: str) -> np.ndarray:
        return np.array([[float(x) for x in row] for row in list(csv.reader(io.StringIO(text)))[1:]])

    shipped, exported = rows(examples.content("ggx-samples").decode()), rows(r.text)
    assert shipped.shape == exported.shape
    np.testing.assert_allclose(shipped, exported, rtol=1e-9, atol=0)
