"""Export file names carry every parameter that differs from the defaults, so two slides
made from different settings never overwrite each other's file."""
from __future__ import annotations

import re


def _name(client, url: str) -> str:
    r = client.get(url)
    assert r.status_code == 200, r.text
    return re.search(r'filename="([^"]+)"', r.headers["content-disposition"]).group(1)


def test_names_differ_where_the_settings_differ(client):
    urls = ["/api/v1/figures/lobe.csv",
            "/api/v1/figures/lobe.csv?theta_i_deg=60",
            "/api/v1/figures/lobe.csv?fresnel=dielectric&ior=1.33",
            "/api/v1/figures/lobe.csv?g2=separable",
            "/api/v1/figures/lobe.csv?kd=0.2",
            "/api/v1/figures/lobe.csv?ndf=gtr&gamma=1.5",
            "/api/v1/figures/lobe.csv?ndf=exp_power&p=0.5",
            "/api/v1/figures/lobe.csv?f0=0.9"]
    names = [_name(client, u) for u in urls]
    assert len(set(names)) == len(names), names


def test_name_spells_the_differences(client):
    name = _name(client, "/api/v1/figures/lobe.csv?theta_i_deg=60&fresnel=dielectric&ior=1.33")
    for part in ("lobe", "ggx", "dielectric", "ior1.33", "theta_i_deg60"):
        assert part in name, name
    assert re.fullmatch(r"[A-Za-z0-9._-]+\.csv", name)


def test_a_get_only_path_answers_post_with_405_and_allow(client):
    """POST to a path that exists only as GET is 405 naming GET, not a 404 'unknown view'."""
    for path in ("/api/v1/health", "/api/v1/models", "/api/v1/lobe"):
        r = client.post(path, json={})
        assert r.status_code == 405, (path, r.status_code, r.text)
        assert r.headers["allow"] == "GET"
    assert client.post("/api/v1/no_such_view", json={}).status_code == 404
