"""material= and vary= on every view (issue 31: "material= and vary= work on every view
that can show them"): each view listed by GET /api/v1/views does what it declares there.
A view that declares `material` draws the measured material (its figure differs from the
same query without it, and names it); one that does not refuses it with a 422 naming
`material` and the reason it declares. An `overlayable` view draws one curve per value
of `vary` (with the material where it takes one); any other refuses `vary` with a 422
naming it (an image or a table is compared side by side, not overlaid)."""
from __future__ import annotations

import json

import pytest

from app.views import VIEWS

#: queries that keep the slow views cheap here (what is checked does not depend on them)
CHEAP = {"tradeoff": "max_budget=256", "advise": "alpha_min=0.5&tol=0.01", "samples": "n=64",
         "sphere": "n=16", "sphere_env": "n=16", "lobe3d": "n_theta=12&n_phi=24", "slice": "n=16"}


def declared(client) -> dict[str, dict]:
    return {v["name"]: v for v in client.get("/api/v1/views").json()}


def test_every_view_is_listed_with_what_it_takes(client):
    views = declared(client)
    assert set(views) == set(VIEWS)
    for name, v in views.items():
        assert isinstance(v["material"], bool) and isinstance(v["overlayable"], bool), name
        assert v["material"] or v["material_refused"].strip(), name


def _get(client, name: str, query: str):
    cheap = CHEAP.get(name, "")
    return client.get(f"/api/v1/figures/{name}.json?{query}{'&' + cheap if cheap else ''}")


def _names_material(figure: dict) -> bool:
    return "gold" in json.dumps(figure).lower()


@pytest.mark.parametrize("name", list(VIEWS))
def test_material_is_drawn_where_declared_and_refused_with_its_reason_elsewhere(client, name):
    view = declared(client)[name]
    r = _get(client, name, "material=gold")
    if not view["material"]:
        assert r.status_code == 422, r.text
        detail = r.json()["detail"][0]
        assert detail["loc"][-1] == "material" and view["material_refused"] in detail["msg"]
        return
    assert r.status_code == 200, r.text
    plain = _get(client, name, "")
    assert plain.status_code == 200, plain.text
    with_material, without = r.json(), plain.json()
    assert with_material["data"] != without["data"] or with_material["layout"] != without["layout"]
    assert _names_material(with_material)


@pytest.mark.parametrize("name", list(VIEWS))
def test_vary_overlays_curves_where_declared_and_is_refused_elsewhere(client, name):
    view = declared(client)[name]
    material = "material=gold&" if view["material"] else ""
    r = _get(client, name, f"{material}vary=alpha&values=0.1,0.4")
    if not view["overlayable"]:
        assert r.status_code == 422, r.text
        assert r.json()["detail"][0]["loc"][-1] == "vary"
        return
    assert r.status_code == 200, r.text
    names = [t.get("name") or "" for t in r.json()["data"]]
    for value in ("0.1", "0.4"):
        assert any(f"alpha={value}" in n for n in names), (value, names)
    if material:
        assert _names_material(r.json())
