"""Browser tests of the exports, the embed pages and the gallery: under a strict
Content-Security-Policy (scripts only from this origin, no inline script), with no
console errors, at a projector's size and a phone's."""
from __future__ import annotations

import json
import re
import urllib.request
from pathlib import Path
from urllib.parse import parse_qs, urlparse

import pytest

from test_page import PANELS, api_requests, wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

# What the pages must work under: no inline script, no eval, nothing from other origins
# (Plotly needs inline styles and data:/blob: images for its modebar and downloads).
STRICT_CSP = ("default-src 'self'; script-src 'self'; style-src 'self' 'unsafe-inline'; "
              "img-src 'self' data: blob:; connect-src 'self'; object-src 'none'; base-uri 'none'")
PHONE = {"width": 390, "height": 844}
EMBED_QUIET = "() => window.__embed && window.__embed.pending() === 0 && window.__embed.drawn()"


def strict_csp(page):
    """Serve every HTML page with STRICT_CSP, whatever the app sends."""
    def handle(route):
        res = route.fetch()
        headers = {k: v for k, v in res.headers.items() if k.lower() != "content-security-policy"}
        headers["content-security-policy"] = STRICT_CSP
        route.fulfill(response=res, headers=headers)
    page.route(lambda url: urlparse(url).path in ("/", "/gallery") or urlparse(url).path.startswith("/embed/"),
               handle)


def views(base_url) -> list[dict]:
    with urllib.request.urlopen(f"{base_url}/api/v1/views") as r:
        return json.load(r)


#: The embeds' cheaper queries of the views that compute for seconds at their defaults:
#: what is checked (the frame filled, the title's lines in it) is the figure's layout,
#: the same at any budget or resolution
CHEAP_EMBED = {"tradeoff": "&max_budget=1024", "advise": "&alpha_min=0.5&tol=0.01",
               "samples": "&n=4096", "sphere_env": "&n=96"}


def test_every_view_embeds_without_errors(page, page_log, base_url):
    strict_csp(page)
    page.set_viewport_size({"width": 640, "height": 440})        # a typical iframe
    for v in views(base_url):
        page.goto(f"/embed/{v['name']}?alpha=0.2{CHEAP_EMBED.get(v['name'], '')}")
        page.wait_for_function(EMBED_QUIET, timeout=60_000)
        box = page.locator("#plot").bounding_box()
        assert box["width"] >= 600 and box["height"] >= 250, (v["name"], box)   # fills the frame
        assert page.evaluate("() => document.documentElement.scrollHeight <= innerHeight + 1")
        assert page.is_hidden("#embed-controls")
        # the title's every line inside the frame and above the plot (a title of several
        # <br> lines had its first line pushed out of the top)
        lines = page.evaluate("""() => [...document.querySelectorAll('#plot .gtitle, #plot .gtitle-subtitle')]
            .map((t) => { const r = t.getBoundingClientRect(); return [r.top, r.bottom, t.textContent]; })""")
        assert lines and all(top >= box["y"] - 0.5 for top, _, _ in lines), (v["name"], lines, box)
    assert page_log.problems() == []


def test_embed_controls_move_the_figure_and_the_url(page, page_log):
    strict_csp(page)
    page.goto("/embed/lobe?alpha=0.2&theta_i_deg=30&controls=1")
    page.wait_for_function(EMBED_QUIET)
    page.wait_for_selector("#embed-controls:not([hidden]) label")     # built from /models, /views
    for label in ("α", "θ", "log scale"):
        assert page.locator("#embed-controls label", has_text=label).count() >= 1
    # every control has a label the browser associates with it
    unlabelled = page.evaluate("""() => [...document.querySelectorAll('#embed-controls input, #embed-controls select')]
        .filter((e) => !(e.labels && e.labels.length) && !e.getAttribute('aria-label')).map((e) => e.id)""")
    assert unlabelled == []
    before = page.evaluate("() => JSON.stringify(document.getElementById('plot').data[0].r)")
    page.fill("#c-theta-i-deg", "60")
    page.wait_for_function(f"(old) => window.__embed.pending() === 0 && JSON.stringify(document.getElementById('plot').data[0].r) !== old",
                           arg=before)
    q = parse_qs(urlparse(page.url).query)
    assert q["theta_i_deg"] == ["60"] and q["controls"] == ["1"]
    page.check("#c-log")
    page.wait_for_function("() => window.__embed.pending() === 0 && document.getElementById('plot').layout.polar.radialaxis.type === 'log'")
    assert page_log.problems() == []


def test_page_export_buttons_download_svg_png_csv(page, page_log):
    strict_csp(page)
    page.goto("/?alpha=0.2")
    wait_quiet(page)
    lobe = page.locator('[data-panel="lobe"]')
    for fmt, magic in (("svg", b"<svg"), ("png", b"\x89PNG"), ("csv", b"# view = lobe")):
        with page.expect_download(timeout=30_000) as dl:
            lobe.locator(f'button[data-format="{fmt}"]').click()
        path = dl.value.path()
        assert dl.value.suggested_filename.endswith(f".{fmt}")
        assert Path(path).read_bytes()[: len(magic)] == magic
    assert page_log.problems() == []


def test_without_server_chromium_the_page_exports_in_the_browser(page, page_log):
    strict_csp(page)
    body = json.dumps({"detail": "No Chromium found. Server-side image export needs a Chromium "
                                 "browser: install it (apt-get install chromium)"})
    page.route("**/api/v1/figures/ndf.svg?*", lambda r: r.fulfill(status=503, body=body,
                                                                    content_type="application/json"))
    page.goto("/")
    wait_quiet(page)
    with page.expect_download(timeout=30_000) as dl:
        page.locator('[data-panel="ndf"] button[data-format="svg"]').click()
    assert dl.value.suggested_filename == "ndf.svg"
    assert Path(dl.value.path()).read_text()[:200].lstrip().startswith("<svg")
    assert "apt-get install chromium" in page.inner_text("#notice")
    assert "in your browser" in page.inner_text("#notice")
    # the only error is the browser's own report of the (simulated) 503
    assert page_log.page_errors == [] and all("503" in e for e in page_log.console_errors)


def test_copy_embed_code_and_link(page, page_log, base_url):
    page.context.grant_permissions(["clipboard-read", "clipboard-write"], origin=base_url)
    page.goto("/?alpha=0.15&theta_i_deg=50&log=true")
    wait_quiet(page)
    button = page.locator('[data-panel="lobe"] button[data-format="embed"]')
    button.click()
    page.wait_for_function("(b) => b.textContent.includes('Copied')", arg=button.element_handle())
    snippet = page.evaluate("() => navigator.clipboard.readText()")
    m = re.fullmatch(r'<iframe src="([^"]+)" width="\d+" height="\d+" title="[^"]*" loading="lazy" style="[^"]*"></iframe>', snippet)
    assert m, snippet
    src = urlparse(m.group(1))
    assert src.path == "/embed/lobe"
    q = {k: v[0] for k, v in parse_qs(src.query).items()}
    assert q["alpha"] == "0.15" and q["theta_i_deg"] == "50" and q["log"] == "true"
    assert "kd" not in q and "fresnel" not in q          # the API's defaults are left out
    page.goto(m.group(1))                          # the snippet's page shows that state
    page.wait_for_function(EMBED_QUIET)
    assert page.evaluate("() => document.getElementById('plot').layout.polar.radialaxis.type") == "log"
    page.go_back()
    wait_quiet(page)
    page.click("#copy-link")
    page.wait_for_function("() => document.getElementById('copy-link').textContent.includes('Copied')")
    assert page.evaluate("() => navigator.clipboard.readText()") == page.url
    assert page_log.problems() == []


def test_hidden_panels_are_not_fetched_until_shown(page, page_log, base_url):
    page.goto("/")
    wait_quiet(page)
    others = [v["name"] for v in views(base_url) if f"plot-{v['name']}" not in PANELS]
    assert others and all(api_requests(page_log, name) == [] for name in others)
    page.check("#show-sphere")
    wait_quiet(page, ids=(*PANELS, "plot-sphere"))
    assert len(api_requests(page_log, "sphere")) == 1
    assert parse_qs(urlparse(page.url).query)["show"] == ["lobe,ndf,g1,albedo,sphere"]
    page.select_option("#sphere-display", "render")
    wait_quiet(page, ids=(*PANELS, "plot-sphere"))
    assert api_requests(page_log, "sphere")[-1]["display"] == "render"
    # a request in flight is kept when its panel leaves the view (a scroll, a panel
    # above it grown): it lands and is drawn, and is not asked for again (the sphere
    # below the fold of a short window)
    size = page.viewport_size
    page.set_viewport_size({"width": size["width"], "height": 560})
    wait_quiet(page, ids=("plot-sphere",))
    held = []
    page.route("**/api/v1/figures/sphere?*", lambda route: held.append(route))
    n = len(api_requests(page_log, "sphere"))
    page.fill("#alpha", "0.4")
    for _ in range(200):
        if held:
            break
        page.wait_for_timeout(50)
    page.evaluate("() => { document.getElementById('panels').scrollTop = 0; }")
    page.wait_for_function("() => !window.__brdf.panels().find((p) => p.name === 'sphere').inView")
    for route in held:
        route.continue_()
    page.wait_for_function("""() => { const p = window.__brdf.panels().find((x) => x.name === 'sphere');
        return !p.inflight && p.current && !p.inView; }""", timeout=15_000)
    assert len(api_requests(page_log, "sphere")) == n + 1 and len(held) == 1
    page.unroute("**/api/v1/figures/sphere?*")
    page.set_viewport_size(size)
    page.uncheck("#show-ndf")
    n = len(api_requests(page_log, "ndf"))
    page.fill("#alpha", "0.5")
    wait_quiet(page, ids=("plot-lobe", "plot-sphere"))
    assert len(api_requests(page_log, "ndf")) == n          # hidden: not fetched
    # the live GPU sphere is a panel like the others: off at first, a toggle in PANELS,
    # named in show=, one row of the grid like the sphere beside it (no empty block)
    assert not page.is_visible("#panel-gpu") and not page.is_checked("#show-gpu")
    page.check("#show-gpu")
    page.wait_for_function("() => window.__gpu && window.__gpu.ok", timeout=60_000)
    wait_quiet(page, ids=("plot-sphere",))
    assert parse_qs(urlparse(page.url).query)["show"] == ["lobe,g1,albedo,sphere,gpu"]
    heights = page.evaluate("""() => ['#panel-gpu', '[data-panel="sphere"]'].map(
        (s) => document.querySelector(s).getBoundingClientRect().height)""")
    assert heights[0] == pytest.approx(heights[1], abs=1)
    assert page_log.problems() == []


def test_every_control_is_labelled_and_keyboard_operable(page, page_log):
    page.goto("/?show=lobe,ndf,g1,albedo,lobe3d,g2,fresnel,sphere,slice")
    wait_quiet(page, ids=("plot-lobe", "plot-sphere", "plot-slice"))
    unlabelled = page.evaluate("""() => [...document.querySelectorAll('input, select, button')]
        .filter((e) => e.offsetParent !== null)
        .filter((e) => !(e.labels && e.labels.length) && !e.getAttribute('aria-label')
                       && !(e.tagName === 'BUTTON' && e.textContent.trim()))
        .map((e) => e.id || e.outerHTML.slice(0, 80))""")
    assert unlabelled == []
    # keyboard: Tab reaches an export button, Enter on it downloads
    page.focus('[data-panel="lobe"] button[data-format="svg"]')
    page.keyboard.press("Shift+Tab")
    page.keyboard.press("Tab")
    assert page.evaluate("() => document.activeElement.dataset.format") == "svg"
    with page.expect_download(timeout=30_000) as dl:
        page.keyboard.press("Enter")
    assert dl.value.suggested_filename.endswith(".svg")
    # arrow keys step a number box
    page.focus("#theta_i")
    page.keyboard.press("ArrowUp")
    assert page.evaluate("() => window.__brdf.state.theta_i_deg") == 45.1     # one slider step
    assert page_log.problems() == []


# Each gallery card's plot as a reader sees it (issue 34: crammed log labels, a right axis
# labelled 0.00309, 0.00179, −0.00081 and a legend that squashed the albedo to a strip):
# per axis, tick labels that overlap one another and linear ticks whose spacing is not a
# round number (1, 2, 2.5 or 5 × 10^k, or 15° and 30° steps of an angle); and the plot area's share of the figure's height
# (of stacked subplots, their extent).
CARD_LOOKS_JS = r"""() => [...document.querySelectorAll('.gallery-card')].filter((card) => card.querySelector('.gallery-plot')).map((card) => {
  const div = card.querySelector('.gallery-plot'), out = { id: card.id, overlaps: [], unround: [] };
  for (const cls of ['xtick', 'ytick', 'y2tick']) {
    const texts = [...div.querySelectorAll(`.cartesianlayer g.${cls} text, .polarlayer g.${cls} text`)]
      .filter((t) => t.getBoundingClientRect().width > 0);
    const boxes = texts.map((t) => t.getBoundingClientRect());
    for (let i = 0; i < boxes.length; i++) for (let j = i + 1; j < boxes.length; j++) {
      const a = boxes[i], b = boxes[j];
      // an x axis's labels rotated alike (long category names): their upright boxes overlap
      // while the text does not; two parallel lines clear each other when their anchors are
      // a line's height apart across the text's direction
      const turn = cls === 'xtick' && texts[i].closest('.cartesianlayer')
        && /rotate\((-?[\d.]+)/.exec(texts[i].getAttribute('transform') || '');
      const clash = turn && Number(turn[1]) !== 0
        ? Math.abs(a.right - b.right) * Math.abs(Math.sin(Number(turn[1]) * Math.PI / 180)) < parseFloat(getComputedStyle(texts[i]).fontSize)
        : a.left < b.right - 1 && b.left < a.right - 1 && a.top < b.bottom - 1 && b.top < a.bottom - 1;
      if (clash) out.overlaps.push([cls, texts[i].textContent, texts[j].textContent]);
    }
    const values = texts.map((t) => t.textContent.replace('\u2212', '-'));
    if (values.length >= 3 && values.every((v) => /^-?\d*\.?\d+$/.test(v))) {
      const step = Math.abs(Number(values[1]) - Number(values[0]));
      const m = step / 10 ** Math.floor(Math.log10(step));
      if (![1, 1.5, 2, 2.5, 3, 5, 10].some((r) => Math.abs(m - r) < 1e-6 * r)) out.unround.push([cls, values.slice(0, 4)]);
    }
  }
  // the plot areas' vertical extent (stacked subplots: from the top one's top to the bottom one's bottom)
  const areas = [...div.querySelectorAll('.nsewdrag, .polarlayer .bg, .polarlayer path.bg')].map((a) => a.getBoundingClientRect());
  const plot = div.getBoundingClientRect();
  out.areaShare = areas.length ? (Math.max(...areas.map((b) => b.bottom)) - Math.min(...areas.map((b) => b.top))) / plot.height : null;
  return out; })"""


def test_gallery_renders_and_every_link_opens_its_state(page, page_log, shots):
    strict_csp(page)
    page.goto("/gallery")
    page.wait_for_function("() => document.querySelectorAll('.gallery-card').length >= 8")
    cards = page.locator(".gallery-card")
    count = cards.count()
    for i in range(count):                      # scroll each into view: figures draw lazily
        cards.nth(i).scroll_into_view_if_needed()
    page.wait_for_function("() => !window.__gallery.pending()", timeout=60_000)
    assert page.evaluate("() => window.__gallery.failed()") == 0
    assert page.evaluate("() => window.__gallery.done()") == count
    page.evaluate("() => window.scrollTo(0, 0)")
    page.screenshot(path=str(shots / "screenshot-gallery.png"))
    for card in page.evaluate(CARD_LOOKS_JS):
        assert card["overlaps"] == [] and card["unround"] == [], card
        assert card["areaShare"] is None or card["areaShare"] >= 0.5, card
    # the views' cards open their state (the capability cards' places: the next test)
    links = page.eval_on_selector_all(".gallery-card a.open", "(as) => as.map((a) => a.href)")
    assert len(links) == count
    views = [link for link in links if urlparse(link).path == "/" and "data=" not in link]
    assert len(views) >= 8
    for link in views:
        q = {k: v[0] for k, v in parse_qs(urlparse(link).query).items()}
        page.goto(link)
        wait_quiet(page, ids=(f"plot-{q['show']}",))
        state = page.evaluate("() => window.__brdf.state")
        assert q["show"] in state["show"]
        assert state["vary"] == q.get("vary") and state["values"] == q.get("values")
        panel = page.evaluate(f"() => window.__brdf.panels().find((p) => p.name === '{q['show']}')")
        assert panel["drawn"] and panel["error"] is None, (link, panel)
        if "vary" in q:                         # the comparison drew one curve per value
            names = page.evaluate(f"() => document.getElementById('plot-{q['show']}').data.map((t) => t.name)")
            for value in q["values"].split(","):
                assert any(f"{q['vary']}={value}" in (n or "") for n in names), (link, names)
    assert page_log.problems() == []


#: the gallery's cards for the capabilities beyond the views (app/gallery/cards.py)
CAPABILITY_CARDS = "[data-kind=dataset], [data-kind=fit], [data-kind=code], [data-kind=lut], [data-kind=conventions]"
CARDS_SETTLED_JS = """(sel) => [...document.querySelectorAll(sel)].every((c) => c.matches('.drawn, .failed'))"""
CARD_CONTENT_JS = """(sel) => [...document.querySelectorAll(sel)].map((c) => ({
  kind: c.dataset.kind, failed: c.matches('.failed'), result: c.querySelector('.gallery-result').textContent,
  code: c.querySelector('pre.gallery-code')?.textContent || null,
  image: c.querySelector('img.gallery-image')?.naturalWidth ?? null,
  traces: document.getElementById(`plot-${c.id}`)?.data?.length ?? null,
  open: c.querySelector('a.open').href, api: [...c.querySelectorAll('.gallery-api a')].map((a) => a.href) }))"""
DATA_DRAWN_JS = """() => (document.getElementById('plot-lobe').layout.annotations || []).some((a) => a.name === 'brdf-data-label')"""


def test_gallery_capability_cards_draw_and_open_their_place(page, page_log):
    """Issue 34: the cards for a data set, a fit, shader code, a LUT and the conventions
    each draw what they say (a data set's points, a fitted model, the real generated
    code, the table's image with its error), and the data set's explorer link opens the
    explorer with the data on the lobe."""
    strict_csp(page)
    page.goto("/gallery")
    page.wait_for_function("() => document.querySelectorAll('.gallery-card').length >= 8")
    cards = page.locator(CAPABILITY_CARDS)
    assert cards.count() >= 5
    for i in range(cards.count()):              # drawn as they scroll into view
        cards.nth(i).scroll_into_view_if_needed()
    page.wait_for_function(CARDS_SETTLED_JS, arg=CAPABILITY_CARDS, timeout=30_000)
    found = {c["kind"]: c for c in page.evaluate(CARD_CONTENT_JS, CAPABILITY_CARDS)}
    assert set(found) == {"dataset", "fit", "code", "lut", "conventions"}
    assert not [c for c in found.values() if c["failed"]], found
    assert found["dataset"]["traces"] >= 2 and found["conventions"]["traces"] >= 2    # model and data; several ecosystems
    assert found["fit"]["traces"] >= 2 and found["fit"]["result"].startswith("Fitted") and "α = " in found["fit"]["result"]
    assert "brdf_local(" in found["code"]["code"] and "Lines" in found["code"]["result"]
    assert found["lut"]["image"] == 32 and "bilinear" in found["lut"]["result"]
    for c in found.values():
        assert c["api"] and c["open"], c
    # the view cards near these began to draw as they came near: let them finish before
    # leaving (a request cut by the navigation would count as failed)
    page.wait_for_function("() => window.__gallery.inFlight() === 0", timeout=30_000)
    # the data set's card opens the explorer with the example data on the lobe, the id
    # handed over and taken out of the URL (the page's URL is the model's state)
    page.goto(found["dataset"]["open"])
    wait_quiet(page, ids=("plot-lobe",))
    page.wait_for_function(DATA_DRAWN_JS, timeout=20_000)
    assert "data=" not in page.url and page.evaluate("() => window.__brdfData.id") in found["dataset"]["open"]
    # the tools' cards open their section of the tools page, scrolled to it
    page.goto(found["lut"]["open"])
    page.wait_for_selector("#tools[data-ready]")
    top = page.evaluate("() => document.getElementById('lut').getBoundingClientRect().top")
    assert page.evaluate("() => scrollY") > 0 and 0 <= top < page.viewport_size["height"] - 200, top
    assert page_log.problems() == []


@pytest.mark.parametrize("path", ["/", "/gallery", "/embed/lobe?controls=1"])
def test_phone_portrait_has_no_sideways_scroll(page, page_log, path, shots):
    page.set_viewport_size(PHONE)
    page.goto(path)
    if path == "/":
        wait_quiet(page)
    elif path.startswith("/embed"):
        page.wait_for_function(EMBED_QUIET)
    else:
        page.wait_for_function("() => document.querySelector('.gallery-card.drawn')")
    assert page.evaluate("() => document.documentElement.scrollWidth <= window.innerWidth")
    if path == "/":
        boxes = [page.locator(f"#{pid}").bounding_box() for pid in PANELS]
        assert all(b["width"] >= 340 and b["height"] >= 250 for b in boxes)
        assert page.locator(".topbar").bounding_box()["height"] <= 90      # the bar does not swallow the page
        page.locator('[data-panel="lobe"]').scroll_into_view_if_needed()
        page.screenshot(path=str(shots / "screenshot-phone.png"), full_page=False)
    assert page_log.problems() == []
