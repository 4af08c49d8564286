"""Every model option of GET /api/v1/models reachable from the page, and pinned models.

The option lists are read from the API (not written down here), so a choice added to
the registry is exercised by these tests without a change to them.
"""
from __future__ import annotations

import json
from urllib.parse import parse_qs, urlparse

import httpx
import pytest

import test_page   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

PANELS = ("plot-lobe", "plot-ndf", "plot-g1", "plot-albedo")


def wait_quiet(page, ids=PANELS, timeout=30_000):
    test_page.wait_quiet(page, ids, timeout)


def url_query(page) -> dict[str, list[str]]:
    return parse_qs(urlparse(page.url).query)


def last_get(log, kind: str) -> dict[str, str]:
    for url in reversed(log.requests):
        u = urlparse(url)
        if u.path == f"/api/v1/figures/{kind}" and u.query:
            return {k: v[-1] for k, v in parse_qs(u.query).items()}
    raise AssertionError(f"no GET of figures/{kind} in {log.requests[-5:]}")


@pytest.fixture(scope="module")
def models(live_server):
    return httpx.get(f"{live_server}/api/v1/models").json()


def select(page, group: str, value: str, ids=PANELS) -> None:
    page.select_option(f"#{group}", value)
    wait_quiet(page, ids)


def panel_errors(page) -> list:
    return page.evaluate("() => window.__brdf.panels().filter((p) => p.visible && p.error)"
                         ".map((p) => p.name + ': ' + p.error)")


def test_every_choice_can_be_selected_and_draws(page, page_log, models):
    """Two panels that every choice reaches (the lobe takes all four options, G1 the
    masking): the four default panels drew the same choices at twice the cost (the
    albedo quadrature of each), 160 s of the suite. Each choice is made from the four
    defaults, chosen back on the page (a reload for each cost ~1 s of Plotly's start)."""
    opts = models["options"]
    ids = ("plot-lobe", "plot-g1")
    seen = 0
    page.goto("/?show=lobe,g1")
    wait_quiet(page, ids)
    for group in ("ndf", "masking", "g2", "fresnel"):
        for choice in opts[group]["choices"]:
            for g in ("masking", "g2", "fresnel", "ndf"):    # the NDF last: the others apply to it
                if page.evaluate("(g) => window.__brdf.state[g]", g) != opts[g]["default"]:
                    select(page, g, opts[g]["default"], ids)
            assert page.evaluate("() => ['ndf', 'masking', 'g2', 'fresnel'].map((g) => window.__brdf.state[g])") \
                == [opts[g]["default"] for g in ("ndf", "masking", "g2", "fresnel")]
            applies = choice.get("applies_to")
            if applies and "ggx" not in applies:        # choose an NDF it applies to first
                select(page, "ndf", applies[0], ids)
            assert not page.evaluate(f"() => document.querySelector('#{group} option[value={choice['name']}]').disabled")
            select(page, group, choice["name"], ids)
            assert page.evaluate("(g) => window.__brdf.state[g]", group) == choice["name"]
            assert not panel_errors(page), (group, choice["name"], panel_errors(page))
            sent = last_get(page_log, "lobe")
            assert sent.get(group, opts[group]["default"]) == choice["name"]
            # the choice's own parameters are shown, with its own range, and sent
            for p in choice.get("params", []):
                row = page.locator(f".param[data-param={p['name']}]:visible")
                assert row.count() == 1, (choice["name"], p["name"])
                box = row.locator("input[type=number]")
                assert float(box.get_attribute("max")) == p["hi"], (choice["name"], p["name"])
                assert float(box.get_attribute("min")) == p["lo"], (choice["name"], p["name"])
                assert float(sent[p["name"]]) == p["default"]
            seen += 1
    assert seen == sum(len(opts[g]["choices"]) for g in ("ndf", "masking", "g2", "fresnel"))
    assert not page_log.problems(), page_log.problems()


def test_choice_params_are_sent_only_with_their_choice(page, page_log):
    ids = ("plot-lobe", "plot-ndf")          # what it reads; the albedo panel only cost time
    page.goto("/?ndf=student_t&gamma=500&show=lobe,ndf")
    wait_quiet(page, ids)
    assert float(last_get(page_log, "ndf")["gamma"]) == 500     # (1.5, 1000]: not clamped to GTR's 10
    select(page, "ndf", "gtr", ids)                                   # GTR's γ has its own range: default
    assert float(last_get(page_log, "ndf")["gamma"]) == 2.0
    select(page, "ndf", "ggx", ids)
    sent = last_get(page_log, "ndf")
    assert "gamma" not in sent and "p" not in sent
    select(page, "fresnel", "conductor", ids)
    sent = last_get(page_log, "lobe")
    assert float(sent["ior"]) == 0.43 and float(sent["k"]) == 2.455 and "f0" not in sent
    assert not page_log.problems(), page_log.problems()


def test_applicability_disables_and_falls_back(page, page_log):
    ids = ("plot-lobe",)                     # the rules live in the sidebar; one panel draws
    page.goto("/?g2=hammon&masking=karis&show=lobe")
    wait_quiet(page, ids)
    select(page, "ndf", "beckmann", ids)                  # Karis and Hammon are GGX-only
    st = page.evaluate("() => window.__brdf.state")
    assert st["masking"] == "smith" and st["g2"] == "height_correlated"
    assert page.evaluate("() => document.querySelector('#g2 option[value=hammon]').disabled")
    assert page.evaluate("() => document.querySelector('#masking option[value=walter]').disabled") is False
    select(page, "ndf", "gtr", ids)                       # isotropic only
    assert page.evaluate("() => document.getElementById('anisotropic').disabled")
    select(page, "ndf", "blinn_phong", ids)
    assert page.evaluate("() => document.getElementById('anisotropic').disabled")
    derived = page.locator("#derived")
    assert derived.is_visible() and "α_p" in derived.inner_text()
    # α = 0.3 (default): α_p = 2/0.09 − 2 = 20.22
    assert "20.22" in derived.inner_text()
    select(page, "ndf", "ggx", ids)
    assert not derived.is_visible()
    assert not page_log.problems(), page_log.problems()


def test_lambda_phi_only_with_a_needs_phi_g2(page, page_log, models):
    needs = [c["name"] for c in models["options"]["g2"]["choices"] if c.get("needs_phi")]
    assert needs
    # the lobe takes every option; the default albedo panel, with a direction-correlated
    # G2, took over the 30 s wait on a loaded machine and tells nothing more here
    ids = ("plot-lobe", "plot-g1")
    page.goto("/?show=lobe,g1")
    wait_quiet(page, ids)
    assert not page.locator("#lambda_phi").is_visible()
    assert "lambda_phi" not in last_get(page_log, "lobe")
    select(page, "g2", needs[0], ids)
    assert page.locator("#lambda_phi").is_visible()
    select(page, "lambda_phi", "van_ginneken", ids)
    assert last_get(page_log, "lobe")["lambda_phi"] == "van_ginneken"
    page.wait_for_function("() => location.search.includes('lambda_phi=van_ginneken')")
    select(page, "g2", "separable", ids)
    assert not page.locator("#lambda_phi").is_visible()
    assert "lambda_phi" not in last_get(page_log, "lobe")
    page.wait_for_function("() => !location.search.includes('lambda_phi')")
    # aniso_map only in the perceptual form
    assert not page.locator("#aniso_map").is_visible()
    page.check("#perceptual")
    wait_quiet(page, ids)
    assert page.locator("#aniso_map").is_visible()
    select(page, "aniso_map", "kulla_conty", ids)
    assert last_get(page_log, "lobe")["aniso_map"] == "kulla_conty"
    assert not page_log.problems(), page_log.problems()


def test_second_lobe_sends_alpha2_and_lobe_mix(page, page_log):
    page.goto("/")
    wait_quiet(page)
    sent = last_get(page_log, "lobe")
    assert "alpha2" not in sent and "lobe_mix" not in sent
    assert not page.locator("#alpha2").is_visible()
    page.check("#second-lobe")
    wait_quiet(page)
    page.fill("#alpha2", "0.08")
    page.wait_for_function("() => window.__brdf.state.alpha2 === 0.08")
    wait_quiet(page)
    sent = last_get(page_log, "lobe")
    assert float(sent["alpha2"]) == 0.08 and 0 < float(sent["lobe_mix"]) <= 1
    page.wait_for_function("() => location.search.includes('alpha2=0.08')")
    page.goto(page.url)                               # the URL restores it
    wait_quiet(page)
    assert page.is_checked("#second-lobe") and page.input_value("#alpha2") == "0.08"
    page.uncheck("#second-lobe")
    wait_quiet(page)
    assert "alpha2" not in last_get(page_log, "lobe")
    assert not page_log.problems(), page_log.problems()


def ndf_names(page) -> list[str]:
    return page.evaluate("() => document.getElementById('plot-ndf').data.map((t) => t.name)")


def test_pins_overlay_persist_and_clear(page, page_log):
    page.goto("/?alpha=0.2")
    wait_quiet(page)
    page.click(".panel[data-panel=ndf] [data-action=pin]")          # ggx, α = 0.2
    wait_quiet(page)
    select(page, "ndf", "beckmann")
    page.click("#pin-current")
    wait_quiet(page)
    select(page, "ndf", "blinn_phong")
    names = ndf_names(page)
    assert len(names) == 3, names
    assert "ggx" in names[0] and "beckmann" in names[1] and "blinn_phong" in names[2] and "now" in names[2]
    pins = url_query(page)["pin"]
    assert pins == ["ndf:ggx,alpha:0.2", "ndf:beckmann,alpha:0.2"]
    # the sidebar lists them; the POST bodies carried them
    assert page.locator("#pin-list li").count() == 2
    posts = [r for r in page_log.requests if r.endswith("/api/v1/figures/ndf")]
    assert posts
    # every curve panel overlays; reload restores
    for kind in ("lobe", "g1", "albedo"):
        n = page.evaluate(f"() => document.getElementById('plot-{kind}').data.length")
        assert n >= 3, (kind, n)
    page.goto(page.url)
    wait_quiet(page)
    assert len(ndf_names(page)) == 3 and page.locator("#pin-list li").count() == 2
    # remove one, then clear
    page.click("#pin-list li:first-child .pin-remove")
    wait_quiet(page)
    assert len(ndf_names(page)) == 2 and url_query(page)["pin"] == ["ndf:beckmann,alpha:0.2"]
    page.click("#pin-clear")
    wait_quiet(page)
    assert len(ndf_names(page)) == 1
    page.wait_for_function("() => !location.search.includes('pin=')")
    assert not page_log.problems(), page_log.problems()


def test_compare_tails_and_screenshot(page, page_log, shots):
    shown = ("plot-lobe", "plot-ndf", "plot-g1", "plot-fresnel")
    page.goto("/?alpha=0.25&show=lobe,ndf,g1,fresnel")
    wait_quiet(page, shown)
    page.click(".panel[data-panel=ndf] [data-action=tails]")
    wait_quiet(page, shown)
    names = ndf_names(page)
    assert [n.split(",")[0] for n in names] == ["ggx", "beckmann", "blinn_phong"], names
    assert page.evaluate("() => document.getElementById('plot-ndf').layout.yaxis.type") == "log"
    assert len(url_query(page)["pin"]) == 3
    # the current model is one of the pins: drawn once, marked "now"
    assert "(now)" in names[0]
    select(page, "ndf", "student_t", shown)
    assert len(ndf_names(page)) == 4
    page.screenshot(path=str(shots / "screenshot-compare.png"))
    assert not page_log.problems(), page_log.problems()


def test_bad_pins_are_left_out_with_a_notice(page, page_log):
    page.goto("/?pin=ndf:nope&pin=ndf:beckmann,masking:karis&pin=ndf:gtr,gamma:50&pin=ndf:beckmann,alpha:0.2")
    wait_quiet(page)
    notes = page.inner_text("#notice-list")
    assert "ndf=nope" in notes and "Karis" in notes and "gamma=50" in notes
    assert json.loads(page.evaluate("() => JSON.stringify(window.__brdf.state.pins)")) == [
        {"ndf": "beckmann", "alpha": 0.2}]
    assert not page_log.problems(), page_log.problems()


def test_albedo_method_and_advice_tolerance_reach_the_api(page, page_log):
    """The albedo panel's method menu and samples box, and the advice panel's tol, are
    sent with their panel's request only, kept in the URL, and drawn (legend, table)."""
    page.goto("/?show=albedo,advise")
    wait_quiet(page, ("plot-albedo", "plot-advise"))
    # samples and seed are the Monte Carlo methods' only: hidden with the quadrature
    assert not page.is_visible("#albedo-samples") and not page.is_visible("#albedo-seed")
    page.select_option("#albedo-method", "mc_vndf")
    assert page.is_visible("#albedo-samples") and page.is_visible("#albedo-seed")
    page.fill("#albedo-samples", "256")
    page.locator("#albedo-samples").dispatch_event("input")
    wait_quiet(page, ("plot-albedo",))
    sent = last_get(page_log, "albedo")
    assert sent["method"] == "mc_vndf" and sent["samples"] == "256"
    names = page.evaluate("() => document.getElementById('plot-albedo').data.map((t) => t.name)")
    assert any("mc_vndf, 256 samples" in (n or "") for n in names), names
    assert "method" not in last_get(page_log, "advise")
    # the heading shows the figure's first line: the recommendation
    assert "Recommended:" in page.inner_text("#h-advise")
    page.fill("#advise-tol", "0.05")
    page.locator("#advise-tol").dispatch_event("input")
    wait_quiet(page, ("plot-advise",))
    assert last_get(page_log, "advise")["tol"] == "0.05"
    query = url_query(page)
    assert query["albedo.method"] == ["mc_vndf"] and query["advise.tol"] == ["0.05"]
    # back to the quadrature: the samples chosen are kept for later but not sent (the
    # API refuses samples where they do not apply)
    page.select_option("#albedo-method", "quadrature")
    wait_quiet(page, ("plot-albedo",))
    assert not page.is_visible("#albedo-samples")
    assert "samples" not in last_get(page_log, "albedo")
    assert url_query(page)["albedo.samples"] == ["256"]
    # auto with a tol: the panel's tol box goes to the request, the legend names the choice
    page.select_option("#albedo-method", "auto")
    page.fill("#albedo-tol", "0.0001")
    page.locator("#albedo-tol").dispatch_event("input")
    wait_quiet(page, ("plot-albedo",))
    sent = last_get(page_log, "albedo")
    assert sent["method"] == "auto" and sent["tol"] == "0.0001" and "samples" not in sent
    names = page.evaluate("() => document.getElementById('plot-albedo').data.map((t) => t.name)")
    assert any("(auto)" in (n or "") for n in names), names
    assert panel_errors(page) == [] and page_log.problems() == []
