"""The gallery: at least eight figures, a card for every capability, every link
answering 200."""
from __future__ import annotations

from urllib.parse import parse_qsl, urlparse

from app.datasets import examples
from app.gallery import ENTRIES, cards
from app.views import VIEWS

#: the capabilities beyond the views, each with at least one card (issue 34)
CAPABILITIES = {"dataset", "fit", "code", "lut", "conventions"}


def test_gallery_lists_at_least_eight_supported_figures(client):
    r = client.get("/api/v1/gallery")
    assert r.status_code == 200
    items = r.json()
    assert len(items) >= 8
    assert len({i["id"] for i in items}) == len(items)
    for item in items:
        sentences = [s for s in item["caption"].replace("e.g.", "eg").split(". ") if s.strip()]
        assert len(sentences) in (2, 3), item["caption"]          # a two-sentence caption (or three)
        assert item["source"] and item["title"]


def test_every_gallery_link_works(client):
    for item in client.get("/api/v1/gallery").json():
        if item["kind"] not in VIEWS:
            continue                                   # the capability cards: the test below
        for key in ("figure", "csv", "embed"):
            r = client.get(item[key])
            assert r.status_code == 200, (item["id"], key, r.text[:300])
        # the explorer link carries the state and shows the figure's panel
        link = urlparse(item["explorer"])
        assert link.path == "/" and client.get(item["explorer"]).status_code == 200
        q = dict(parse_qsl(link.query))
        assert q["show"] == item["kind"]
        for k, v in item["state"].items():
            assert q[k] == (str(v).lower() if isinstance(v, bool) else str(v))
        # and the same state, without the overlay, is a valid figure request for the page
        plain = {k: v for k, v in q.items() if k not in ("show", "vary", "values")}
        assert client.get(f"/api/v1/figures/{item['kind']}", params=plain).status_code == 200


def test_unsupported_states_are_left_out(client, monkeypatch):
    import app.gallery as gallery
    bad = gallery.Entry("bad", "t", "One. Two.", "ndf", ({"ndf": "no_such_ndf"},), "s")
    fallback = gallery.Entry("fallback", "t", "One. Two.", "ndf",
                             ({"ndf": "no_such_ndf"}, {"ndf": "beckmann"}), "s")
    monkeypatch.setattr(gallery, "ENTRIES", (*ENTRIES, bad, fallback))
    items = {i["id"]: i for i in client.get("/api/v1/gallery").json()}
    assert "bad" not in items and items["fallback"]["state"] == {"ndf": "beckmann"}


def test_pages_are_served(client):
    for path in ("/gallery", "/embed/lobe", "/embed/sphere?controls=1"):
        r = client.get(path)
        assert r.status_code == 200 and r.headers["content-type"].startswith("text/html")
    r = client.get("/embed/no_such_view")
    assert r.status_code == 404 and "one of" in r.json()["detail"][0]["msg"]


def test_a_card_for_each_newer_capability(client):
    """The principled model, an environment, a measured material and a table each have a
    card, and each card's figure draws what it says (issue 34: the gallery showed none)."""
    items = client.get("/api/v1/gallery").json()
    principled = [i for i in items if i["state"].get("model") == "principled"]
    assert {"lobe", "sphere_env"} <= {i["kind"] for i in principled}
    assert any(i["state"].get("material") for i in items)
    table = next(i for i in items if "table" in str(i["state"].get("values", "")))
    assert client.get(table["figure"]).status_code == 200
    # the table's curve lies on the quadrature's within the table's own stated bound
    data = client.get("/api/v1/albedo", params={"alpha": 0.5, "fresnel": "none", "method": "table"}).json()
    exact = client.get("/api/v1/albedo", params={"alpha": 0.5, "fresnel": "none", "mu": ",".join(map(str, data["mu"]))}).json()
    for e_table, e_exact, bound, qerr in zip(data["E"], exact["E"], data["E_error"], exact["E_error"]):
        assert abs(e_table - e_exact) <= bound + qerr
    copper = next(i for i in items if i["state"].get("material") == "copper")
    F = client.get("/api/v1/fresnel", params=copper["state"]).json()["F"]
    assert F[0] > 0.5 and abs(F[-1] - 1.0) < 1e-9       # a conductor: high at 0°, 1 at grazing


def _get(client, url: str, media: str):
    r = client.get(url)
    assert r.status_code == 200, (url, r.text[:300])
    assert r.headers["content-type"].split(";")[0] == media, (url, r.headers["content-type"])
    return r


def test_a_card_for_every_capability_and_every_link_answers(client):
    """Issue 34: a card for each capability (data set, fit, shader code, LUT, conventions,
    and the views), each with an open link into the product and raw API links, every URL
    it carries answering 200 with the media type it states."""
    items = client.get("/api/v1/gallery").json()
    kinds = {i["kind"] for i in items}
    assert CAPABILITIES <= kinds
    assert len(kinds & set(VIEWS)) >= 8                 # the views' cards are still there
    for item in (i for i in items if i["kind"] in CAPABILITIES):
        assert item["links"] and item["open"]["label"].endswith("→")
        _get(client, item["open"]["href"].split("#")[0], "text/html")
        for link in item["links"]:
            _get(client, link["href"].split("#")[0], link["type"])
        if "figure" in item:
            assert set(_get(client, item["figure"], "application/json").json()) >= {"data", "layout"}
        if "image" in item:
            assert _get(client, item["image"]["src"], "image/png").content.startswith(b"\x89PNG")
            assert "error" in _get(client, item["image"]["summary"], "application/json").json()
        if "excerpt" in item:
            assert "brdf_local(" in _get(client, item["excerpt"]["href"], "text/plain").text
        if "fit" in item:
            r = client.post(item["fit"]["url"], json=item["fit"]["body"])
            assert r.status_code == 200, r.text[:300]
            fitted = r.json()
            _get(client, item["fit"]["figure"] + "&" + cards.query(fitted["model"]), "application/json")
            # the caption: a diffuse term the GGX samples (k_d = 0) do not have, and a warning
            # that Beckmann does not describe them
            assert item["fit"]["body"]["model"]["kd"] == 0 and fitted["params"]["kd"] > 0.1
            assert fitted["misfit"]["relative_rms"] > fitted["misfit"]["threshold"]


def test_data_cards_use_the_example_and_say_it_is_synthetic(client):
    """The data-set and fit cards open the server's example in the explorer, and the
    data-set card says the data are synthetic (the project ships no measured data)."""
    items = client.get("/api/v1/gallery").json()
    example_id = examples.example_id("ggx-samples")
    for item in (i for i in items if i["kind"] in ("dataset", "fit")):
        assert example_id in item["open"]["href"] and example_id in str(item)
    data = next(i for i in items if i["kind"] == "dataset")
    assert data["caption"].startswith("Synthetic samples")


def test_export_gallery_writes_the_views_figures_only(tmp_path, monkeypatch):
    """brdf-explorer export-gallery exports each view card's figure; the capability cards
    are no view's export (their files are their API links) and are left out."""
    from app.cli import exports
    jobs = []
    monkeypatch.setattr(exports, "run_exports", lambda given, **_: jobs.extend(given) or 0)
    assert exports.gallery([str(tmp_path), "--formats", "csv"]) == 0
    kinds = {job[0] for job in jobs}
    assert kinds and kinds <= set(VIEWS) and not kinds & CAPABILITIES
