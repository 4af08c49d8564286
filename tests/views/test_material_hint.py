"""A near-miss material name gets a suggestion (issue 34: material=Gold)."""
from __future__ import annotations


def test_capitalised_material_suggests_the_slug(client):
    r = client.get("/api/v1/lobe", params={"material": "Gold", "n": 16})
    assert r.status_code == 422
    assert "did you mean gold" in r.text


def test_unknown_material_points_at_the_list(client):
    r = client.get("/api/v1/lobe", params={"material": "xyzzy", "n": 16})
    assert r.status_code == 422
    assert "/api/v1/materials" in r.text and "did you mean" not in r.text
