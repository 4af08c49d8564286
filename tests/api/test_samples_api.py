"""GET /api/v1/samples and /api/v1/figures/samples."""
from __future__ import annotations

import numpy as np
import pytest

from app.model import make_spec


@pytest.mark.parametrize("sampler", ["uniform", "cosine", "ndf", "vndf"])
def test_samples_are_unit_directions_with_their_pdf(client, sampler):
    r = client.get("/api/v1/samples", params={"sampler": sampler, "n": 3000, "seed": 4,
                                              "theta_i_deg": 60, "ndf": "beckmann", "alpha": 0.4})
    assert r.status_code == 200, r.text
    d = r.json()
    l = np.column_stack([d["x"], d["y"], d["z"]])
    assert l.shape == (3000, 3)
    np.testing.assert_allclose(np.linalg.norm(l, axis=1), 1.0, atol=1e-12)
    pdf, w = np.array(d["pdf"]), np.array(d["weight"])
    assert np.all(pdf > 0) and np.all(w >= 0)
    # weight = f·cos θ_l / pdf, with f from the BRDF itself (independent of the sampler)
    brdf = make_spec(ndf="beckmann", alpha=0.4).brdf()
    v = np.array([np.sin(np.pi / 3), 0.0, 0.5])
    f = brdf.f(l, np.broadcast_to(v, l.shape))
    expected = np.where(l[:, 2] > 0, f * np.maximum(l[:, 2], 0) / pdf, 0.0)
    np.testing.assert_allclose(w, expected, rtol=1e-9, atol=1e-15)
    assert d["E"] == pytest.approx(w.mean())
    assert d["p_value"] >= 1e-4 and d["dof"] >= 5


def test_seed_reproduces_and_changes(client):
    a = client.get("/api/v1/samples?n=50&seed=1").json()
    b = client.get("/api/v1/samples?n=50&seed=1").json()
    c = client.get("/api/v1/samples?n=50&seed=2").json()
    assert a["x"] == b["x"] and a["x"] != c["x"]


def test_limit_is_named(client):
    r = client.get("/api/v1/samples?n=200001")
    assert r.status_code == 422
    assert "BRDF_MAX_SAMPLES" in r.text and r.json()["detail"][0]["loc"] == ["query", "n"]


def test_vndf_without_sampler_is_422(client):
    r = client.get("/api/v1/samples?sampler=vndf&ndf=gtr&alpha=0.3")
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"] == ["query", "sampler"]
    assert "no vndf sampler for ndf=gtr" in r.text


def test_bad_sampler_name_is_422(client):
    assert client.get("/api/v1/samples?sampler=importance").status_code == 422


def test_figure_has_both_panels_and_the_chi_square(client):
    r = client.get("/api/v1/figures/samples", params={"sampler": "ndf", "n": 2000, "alpha": 0.2})
    assert r.status_code == 200, r.text
    fig = r.json()
    assert [t["type"] for t in fig["data"]] == ["histogram2d", "histogram2d"]
    title = fig["layout"]["title"]["text"]
    assert "χ²=" in title and "p=" in title
