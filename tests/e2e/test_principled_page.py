"""The principled BRDF (Burley 2012) on the page: chosen in the sidebar, its controls
built from GET /api/v1/principled, sent to every view that takes it (and only its own
parameters), kept in the link, pinned, embedded; a view that does not take it says so.
"""
from __future__ import annotations

import json
from urllib.parse import parse_qs, urlparse

import httpx
import pytest

from test_page import api_requests, move_slider, query, wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

LOBE_R_JS = "() => JSON.stringify(document.getElementById('plot-lobe').data[0].r)"
SOURCE_JS = "() => document.getElementById('plot-sphere_env').data[0].source"
#: Sidebar controls of the microfacet model alone (the API refuses them with model=principled).
MICROFACET_ONLY = ("#ndf", "#alpha", "#kd", "#fresnel", "#g2", "#masking", "#perceptual")
PRINCIPLED_CONTROLS = ("#principled-metallic", "#principled-roughness", "#principled-clearcoat-gloss",
                       "#principled-lobe", "#principled-channel", "#principled-base-color")


@pytest.fixture(scope="module")
def catalogue(live_server):
    return httpx.get(f"{live_server}/api/v1/principled").json()


def visible(page, selectors) -> list[str]:
    return [s for s in selectors if page.is_visible(s)]


def test_the_catalogue_lists_the_views_that_take_the_principled_model(live_server, catalogue):
    """The page reads which panels can draw the principled model from the catalogue: it
    must be what the views answer."""
    views = [v["name"] for v in httpx.get(f"{live_server}/api/v1/views").json()]
    assert set(catalogue["views"]) | set(catalogue["microfacet_only"]) == set(views)
    for name in views:
        r = httpx.get(f"{live_server}/api/v1/figures/{name}", params={"model": "principled"}, timeout=120)
        if name in catalogue["views"]:
            assert r.status_code == 200, (name, r.text[:300])
        else:
            assert r.status_code == 422 and r.json()["detail"][0]["loc"][-1] == "model", (name, r.text[:300])


def test_choosing_principled_shows_its_controls_and_redraws(page, page_log, catalogue):
    page.goto("/")
    wait_quiet(page)
    assert visible(page, MICROFACET_ONLY) == list(MICROFACET_ONLY)
    assert visible(page, PRINCIPLED_CONTROLS) == []

    page.select_option("#model", "principled")
    wait_quiet(page)
    assert visible(page, PRINCIPLED_CONTROLS) == list(PRINCIPLED_CONTROLS)
    assert visible(page, MICROFACET_ONLY) == []
    assert page.is_visible("#theta_i")                            # the incidence is both models'
    # each slider has the paper's range; the options are menus of the catalogue's choices
    for p in catalogue["params"]:
        box = page.locator(f"#principled-{p['name'].replace('_', '-')}")
        assert (float(box.get_attribute("min")), float(box.get_attribute("max"))) == (p["lo"], p["hi"])
        assert float(box.input_value()) == p["default"]
    lobes = page.eval_on_selector_all("#principled-lobe option", "(os) => os.map((o) => o.value)")
    assert lobes == [c["name"] for c in catalogue["options"]["lobe"]["choices"]]

    # the request is the principled model's: no microfacet parameter goes with it
    sent = api_requests(page_log, "lobe")[-1]
    takes = {"model", "base_color", *(p["name"] for p in catalogue["params"]), *catalogue["options"]}
    assert sent["model"] == "principled"
    assert set(sent) - takes <= {"theta_i_deg", "phi_i_deg", "n", "cosine", "log"}, sent
    assert api_requests(page_log, "ndf")[-1]["model"] == "principled"

    before = page.evaluate(LOBE_R_JS)
    move_slider(page, "principled-metallic-slider", 1)
    page.wait_for_function(f"(b) => ({LOBE_R_JS})() !== b", arg=before, timeout=30_000)
    wait_quiet(page)
    sent = api_requests(page_log, "lobe")[-1]
    assert (sent["model"], sent["metallic"]) == ("principled", "1")
    page.wait_for_function("() => location.search.includes('metallic=1')")
    assert query(page)["model"] == "principled" and "alpha" not in query(page)

    page.select_option("#principled-lobe", "specular")
    wait_quiet(page)
    assert api_requests(page_log, "lobe")[-1]["lobe"] == "specular"
    assert page.is_visible("#principled-lobe-info")

    # back to the microfacet model: its controls and its values are as they were
    page.select_option("#model", "microfacet")
    wait_quiet(page)
    assert visible(page, MICROFACET_ONLY) == list(MICROFACET_ONLY)
    assert visible(page, PRINCIPLED_CONTROLS) == []
    sent = api_requests(page_log, "lobe")[-1]
    assert "model" not in sent and "metallic" not in sent and sent["alpha"] == "0.3"
    assert page_log.problems() == []


def test_a_link_restores_the_principled_controls_and_the_sphere_follows(page, page_log):
    page.goto("/?model=principled&metallic=1&roughness=0.3&show=sphere_env")
    wait_quiet(page, ids=("plot-sphere_env",), timeout=120_000)
    assert page.input_value("#model") == "principled"
    assert page.input_value("#principled-metallic") == "1"
    assert page.input_value("#principled-metallic-slider") == "1"
    assert page.input_value("#principled-roughness") == "0.3"
    assert visible(page, MICROFACET_ONLY) == []
    assert page.is_hidden("#notice")
    sent = api_requests(page_log, "sphere_env")[-1]
    assert (sent["model"], sent["metallic"], sent["roughness"]) == ("principled", "1", "0.3")

    # a colour and a lobe of a link show in their controls; moving metallic redraws the sphere
    page.goto("/?model=principled&metallic=1&roughness=0.3&base_color=0.2,0.4,0.6&lobe=specular"
              "&clearcoat=0.5&show=sphere_env")
    wait_quiet(page, ids=("plot-sphere_env",), timeout=120_000)
    assert page.input_value("#principled-base-color") == "0.2,0.4,0.6"
    assert page.input_value("#principled-base-color-picker") == "#336699"
    assert page.input_value("#principled-lobe") == "specular"
    assert api_requests(page_log, "sphere_env")[-1]["base_color"] == "0.2,0.4,0.6"
    before = page.evaluate(SOURCE_JS)
    page.fill("#principled-metallic", "0.2")
    page.wait_for_function(f"(b) => ({SOURCE_JS})() !== b", arg=before, timeout=120_000)
    assert api_requests(page_log, "sphere_env")[-1]["metallic"] == "0.2"

    # the page writes the state back, and that link restores it exactly
    wait_quiet(page, ids=("plot-sphere_env",), timeout=120_000)
    state = page.evaluate("() => JSON.stringify(window.__brdf.state)")
    page.goto(page.url)
    wait_quiet(page, ids=("plot-sphere_env",), timeout=120_000)
    assert page.evaluate("() => JSON.stringify(window.__brdf.state)") == state
    assert page_log.problems() == []


def test_a_link_with_a_parameter_the_model_does_not_take_says_so(page, page_log):
    page.goto("/?model=principled&alpha=0.2&metallic=2&anisotropic=0.5&principled_multiscatter=kulla_conty")
    wait_quiet(page)
    notice = page.inner_text("#notice")
    assert "alpha" in notice and "metallic=2" in notice and "Kulla-Conty" in notice, notice
    sent = api_requests(page_log, "lobe")[-1]
    assert "alpha" not in sent and sent["metallic"] == "1" and sent["principled_multiscatter"] == "none"
    assert page.is_disabled("#principled-multiscatter option[value=kulla_conty]")
    assert page_log.problems() == []


def test_a_view_that_does_not_take_the_model_says_so(page, page_log, catalogue):
    assert "checks" in catalogue["microfacet_only"]
    page.goto("/?model=principled&show=lobe,checks")
    wait_quiet(page, ids=("plot-lobe",))
    note = page.locator("#note-checks")
    assert note.is_visible() and "microfacet model only" in note.inner_text()
    assert page.is_hidden("#plot-checks") and page.is_hidden("#error-line")
    assert not [r for r in api_requests(page_log, "checks") if r.get("model") == "principled"]
    # the microfacet model: the same panel draws
    page.select_option("#model", "microfacet")
    wait_quiet(page, ids=("plot-lobe", "plot-checks"), timeout=60_000)
    assert note.is_hidden() and page.is_visible("#plot-checks")
    assert page_log.problems() == []


def test_pins_compare_principled_and_microfacet_models(page, page_log):
    page.goto("/?model=principled&metallic=1&base_color=0.2,0.4,0.6")
    wait_quiet(page)
    page.click("#pin-current")
    page.select_option("#model", "microfacet")
    wait_quiet(page)
    pins = json.loads(page.evaluate("() => JSON.stringify(window.__brdf.state.pins)"))
    assert pins == [{"model": "principled", "base_color": "0.2,0.4,0.6", "metallic": 1}]
    page.wait_for_function("() => location.search.includes('pin=')")
    assert parse_qs(urlparse(page.url).query)["pin"] == ["model:principled,base_color:0.2/0.4/0.6,metallic:1"]
    labels = page.eval_on_selector_all("#pin-list .pin-label", "(ls) => ls.map((l) => l.textContent)")
    assert labels == ["principled r=0.5, base_color=0.2,0.4,0.6, metallic=1"]
    # the link keeps the pin
    page.goto(page.url)
    wait_quiet(page)
    assert json.loads(page.evaluate("() => JSON.stringify(window.__brdf.state.pins)")) == pins
    assert page_log.problems() == []


def test_an_embed_of_the_principled_model_moves_its_roughness(page, page_log):
    page.goto("/embed/lobe?model=principled&metallic=1&controls=1")
    page.wait_for_function("() => window.__embed && window.__embed.pending() === 0 && window.__embed.drawn()",
                           timeout=30_000)
    page.wait_for_selector("#c-roughness")
    assert page.locator("#c-alpha").count() == 0
    page.fill("#c-roughness", "0.3")
    page.wait_for_function("() => window.__embed.pending() === 0 && location.search.includes('roughness=0.3')")
    sent = api_requests(page_log, "lobe")[-1]
    assert (sent["model"], sent["roughness"]) == ("principled", "0.3") and "alpha" not in sent
    assert page_log.problems() == []


def test_screenshot_of_the_principled_page(page, page_log, shots):
    page.goto("/?model=principled&metallic=0.6&roughness=0.35&sheen=0.5&show=lobe,ndf,sphere_env,principled_albedo")
    wait_quiet(page, ids=("plot-lobe", "plot-ndf", "plot-sphere_env", "plot-principled_albedo"), timeout=120_000)
    assert page.input_value("#model") == "principled" and page.is_visible("#principled-metallic")
    assert api_requests(page_log, "principled_albedo")[-1]["model"] == "principled"
    page.evaluate("() => document.getElementById('panels').scrollTo(0, 0)")
    page.screenshot(path=str(shots / "screenshot-principled.png"))
    assert page_log.problems() == []
