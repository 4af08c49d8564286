"""The page as modules: state in the URL, one draw per panel per frame, embeds that fit
their frame, slide-size exports, a page a newcomer can read (headings, captions, the
panel list at the top, the phone layout, unknown parameters flagged).

Screenshots of the page, the phone, an embed and a panel's PNG export go to the `shots`
directory (a temporary one; bench/screenshots.py refreshes docs/ from them).
"""
from __future__ import annotations

import json
import struct
from pathlib import Path
from urllib.parse import parse_qs, urlparse

import pytest

from test_page import PANELS, wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

ROOT = Path(__file__).resolve().parents[2]
EMBED_QUIET = "() => window.__embed && window.__embed.pending() === 0 && window.__embed.drawn()"


def png_size(data: bytes) -> tuple[int, int]:
    """Width and height from a PNG's IHDR chunk (PNG spec, section 11.2.2)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n" and data[12:16] == b"IHDR"
    return struct.unpack(">II", data[16:24])


def rect(page, selector: str) -> dict:
    return page.evaluate("""(sel) => { const r = document.querySelector(sel).getBoundingClientRect();
        return { top: r.top, bottom: r.bottom, left: r.left, right: r.right, height: r.height }; }""", selector)


def inside_viewport(page, selector: str) -> bool:
    r = rect(page, selector)
    size = page.viewport_size
    return r["height"] > 0 and r["top"] >= -1 and r["bottom"] <= size["height"] + 1 \
        and r["left"] >= -1 and r["right"] <= size["width"] + 1


# ------------------------------------------------------------------ state and drawing

def test_url_state_round_trip(page, page_log):
    url = ("/?ndf=beckmann&alpha=0.12&anisotropic=&alpha_y=0.3&theta_i_deg=33.5&phi_i_deg=20"
           "&fresnel=dielectric&ior=1.7&log=true&ndf.cosine=true&show=lobe,ndf,fresnel"
           "&pin=ndf:ggx,alpha:0.2")
    page.goto(url.replace("anisotropic=&", ""))
    wait_quiet(page, ids=("plot-lobe", "plot-ndf", "plot-fresnel"))
    state = json.loads(page.evaluate("() => JSON.stringify(window.__brdf.state)"))
    assert (state["ndf"], state["alpha"], state["alpha_y"], state["theta_i_deg"]) == ("beckmann", 0.12, 0.3, 33.5)
    assert state["anisotropic"] and state["log"] and state["ndf.cosine"] and state["ior"] == 1.7
    assert state["show"] == ["lobe", "ndf", "fresnel"]
    assert state["pins"] == [{"ndf": "ggx", "alpha": 0.2}]
    page.wait_for_function("() => window.__brdf.pending() === 0")
    written = page.url
    # the page writes the same state back, and that link restores it exactly
    page.goto(written)
    wait_quiet(page, ids=("plot-lobe", "plot-ndf", "plot-fresnel"))
    assert json.loads(page.evaluate("() => JSON.stringify(window.__brdf.state)")) == state
    assert page.url == written
    assert page_log.problems() == []


BURST_JS = """async () => {
  // a draw's frame: the document timeline's time, which is the frame's own timestamp for
  // everything that runs in it (a counter bumped by a rAF callback of ours would depend
  // on the order of the page's own rAF callbacks within the frame)
  const draws = [];
  for (const d of document.querySelectorAll('.plot')) {
    d.addEventListener(window.__brdf.drawEvent, () => draws.push([d.id, document.timeline.currentTime]));
  }
  const slider = document.getElementById('alpha-slider');
  for (let k = 0; k < 40; k++) {            // one burst: 40 moves in one task
    slider.value = String(300 + 10 * k);
    slider.dispatchEvent(new Event('input', { bubbles: true }));
  }
  await new Promise((r) => { const w = () => (window.__brdf.pending() ? setTimeout(w, 5) : r()); setTimeout(w, 5); });
  await new Promise((r) => setTimeout(r, 100));
  return { draws, alpha: window.__brdf.state.alpha };
}"""


def test_a_burst_of_moves_draws_each_panel_at_most_once_a_frame_and_the_newest_state(page, page_log):
    page.goto("/")
    wait_quiet(page)
    n_before = len(page_log.requests)
    out = page.evaluate(BURST_JS)
    per_frame = {}
    for pid, frame in out["draws"]:
        per_frame[(pid, frame)] = per_frame.get((pid, frame), 0) + 1
    assert max(per_frame.values()) == 1, per_frame
    # a burst costs each panel at most two requests in flight (scheduler.js MAX_IN_FLIGHT)
    # and one for the newest state
    figures = [u for u in page_log.requests[n_before:] if "/api/v1/figures/" in u]
    for name in ("lobe", "ndf", "g1", "albedo"):
        assert 1 <= sum(f"/figures/{name}?" in u for u in figures) <= 3
    # what is drawn is the newest state: the lobe as the API gives it for that α
    alpha = out["alpha"]
    assert page.evaluate("() => window.__brdf.panels().every((p) => !p.visible || p.current)")
    drawn = page.evaluate("""async (alpha) => {
        const div = document.getElementById('plot-lobe');
        const body = await (await fetch(window.__brdf.url('lobe'))).json();
        const same = (a, b) => a.length === b.length && Array.from(a).every((x, i) => Math.abs(x - b[i]) <= 1e-6 * Math.abs(b[i]) + 1e-12);
        return { url: window.__brdf.url('lobe'), same: same(div.data[0].r, body.data[0].r) }; }""", alpha)
    assert f"alpha={alpha}" in drawn["url"] and drawn["same"]
    assert page_log.problems() == []


def test_every_panel_draws(page, page_log, base_url):
    names = [v["name"] for v in page.request.get(f"{base_url}/api/v1/views").json()]
    page.goto("/?show=" + ",".join(names))
    wait_quiet(page, ids=[f"plot-{n}" for n in names], timeout=60_000)
    panels = page.evaluate("() => window.__brdf.panels()")
    assert [p["name"] for p in panels if p["drawn"] and not p["error"]] == [p["name"] for p in panels]
    assert page_log.problems() == []


def test_panels_out_of_view_are_fetched_when_they_scroll_in(page, page_log, base_url):
    names = [v["name"] for v in page.request.get(f"{base_url}/api/v1/views").json()]
    page.goto("/?show=" + ",".join(names))
    wait_quiet(page, ids=["plot-lobe"])
    last = names[-1] if names[-1] not in ("lobe", "ndf", "g1", "albedo") else names[-2]
    assert not [u for u in page_log.requests if f"/figures/{last}?" in u]
    wait_quiet(page, ids=[f"plot-{last}"], timeout=60_000)
    assert [u for u in page_log.requests if f"/figures/{last}?" in u]
    assert page_log.problems() == []


def test_heavy_images_come_coarser_while_a_slider_is_held(page, page_log, base_url):
    view = next(v for v in page.request.get(f"{base_url}/api/v1/views").json() if v["name"] == "lobe3d")
    full = {f["name"]: f["default"] for f in view["fields"] if f["name"] in ("n_theta", "n_phi")}
    page.goto("/?show=lobe,lobe3d")
    wait_quiet(page, ids=("plot-lobe", "plot-lobe3d"))

    def last_lobe3d():
        u = urlparse([x for x in page_log.requests if "/figures/lobe3d?" in x][-1])
        return {k: v[-1] for k, v in parse_qs(u.query).items()}

    assert "n_theta" not in last_lobe3d()
    page.evaluate("""() => { const s = document.getElementById('alpha-slider');
        s.dispatchEvent(new PointerEvent('pointerdown', { bubbles: true }));
        s.value = String(Number(s.value) - 40); s.dispatchEvent(new Event('input', { bubbles: true })); }""")
    wait_quiet(page, ids=("plot-lobe3d",))
    held = last_lobe3d()
    assert 2 <= int(held["n_theta"]) <= full["n_theta"] // 2 + 1 and int(held["n_phi"]) <= full["n_phi"] // 2 + 1
    page.evaluate("""() => { const s = document.getElementById('alpha-slider');
        s.dispatchEvent(new Event('change', { bubbles: true }));
        s.dispatchEvent(new PointerEvent('pointerup', { bubbles: true })); }""")
    wait_quiet(page, ids=("plot-lobe3d",))
    released = last_lobe3d()
    assert "n_theta" not in released and released["alpha"] == held["alpha"]
    assert page_log.problems() == []


def test_another_module_can_add_query_parameters(page, page_log):
    """window.__brdf.setExtra: kept in the URL, sent to the views that declare it."""
    page.goto("/?show=lobe,albedo")
    wait_quiet(page, ids=("plot-lobe", "plot-albedo"))
    page.evaluate("() => window.__brdf.setExtra({ mu: '0.5,1' })")      # albedo declares mu, the lobe does not
    wait_quiet(page, ids=("plot-lobe", "plot-albedo"))
    assert "mu=0.5" in page.evaluate("() => window.__brdf.url('albedo')")
    assert "mu=" not in page.evaluate("() => window.__brdf.url('lobe')")
    assert parse_qs(urlparse(page.url).query)["mu"] == ["0.5,1"]
    assert page_log.problems() == []


# ----------------------------------------------------------------- a readable page

def test_unknown_url_parameter_is_flagged(page, page_log):
    page.goto("/?alpah=0.2&ndf=beckmann")
    wait_quiet(page)
    notice = page.locator("#notice")
    assert notice.is_visible()
    assert "alpah" in notice.inner_text()
    assert page.evaluate("() => window.__brdf.state.ndf") == "beckmann"
    assert page_log.problems() == []


def test_headings_render_names_as_names_and_captions_say_what_each_plot_shows(page, page_log, base_url):
    names = [v["name"] for v in page.request.get(f"{base_url}/api/v1/views").json()]
    page.goto("/?show=g2,lobe")
    wait_quiet(page, ids=("plot-g2", "plot-lobe"))
    # a subscript is an index (θ_i, G_1, E_avg), never half of a name
    html = page.evaluate("""async () => { const { richText } = await import('/static/js/base/dom.js');
        const p = document.createElement('p');
        p.append(richText('G2 — ggx, height_correlated, lambda_phi=1, θ_i=45°, E_avg, G_1'));
        return p.innerHTML; }""")
    assert html == ("G2 — ggx, height_correlated, lambda_phi=1, θ<sub>i</sub>=45°, "
                    "E<sub>avg</sub>, G<sub>1</sub>"), html
    subs = page.evaluate("() => [...document.querySelectorAll('sub')].map((s) => s.textContent)")
    assert subs and all(len(s) <= 3 for s in subs), subs
    captions = page.evaluate("""() => [...document.querySelectorAll('.panel .caption')]
        .map((c) => [c.closest('.panel').dataset.panel, c.textContent])""")
    assert sorted(n for n, _ in captions) == sorted(names)
    for name, text in captions:
        assert text.endswith(".") and 20 < len(text) < 140 and text.count(". ") == 0, (name, text)
        assert "MATH" + ".md" not in text and "seed 0" not in text
    # the lobe's cosine toggle weights by the direction that varies: f·cos θ_o
    assert "cos θo" in page.locator('label[for="cosine"]').inner_text()
    assert page_log.problems() == []


def test_figure_subscripts_are_drawn_as_subscripts_and_read_as_before_by_the_page(page, page_log):
    """The figures write θ<sub>m</sub> (issue 11): the chart draws the index as a
    subscript, and what the page reads of a figure as text (a panel's heading, an embed's
    document title) says θ_m as before, which richText draws as a subscript, from text
    nodes only."""
    page.goto("/?show=lobe,ndf")
    wait_quiet(page, ids=("plot-lobe", "plot-ndf"))
    # the axis title "θ<sub>m</sub> (degrees)" is drawn as θ, a subscript "m", no markup
    xtitle = page.evaluate("""() => { const t = document.querySelector('#plot-ndf .chart-xtitle');
        return { text: t.textContent, subs: [...t.querySelectorAll('sub')].map((s) => s.textContent) }; }""")
    assert xtitle["text"] == "θm (degrees)" and xtitle["subs"] == ["m"], xtitle
    legend = page.evaluate("() => document.querySelector('#plot-ndf').data[0].name")
    assert legend == "D(θ<sub>m</sub>)"
    # the lobe panel's heading reads the figure's title: θ_i, drawn as θ<sub>i</sub>, as before
    heading = page.locator('[data-panel="lobe"] h2 .sub').inner_html()
    assert heading.endswith("θ<sub>i</sub>=45°") and "&lt;" not in heading, heading
    out = json.loads(page.evaluate("""async () => {
        const { richText, plainIndex } = await import('/static/js/base/dom.js');
        const { titleText, fitLayout } = await import('/static/js/panels/layout.js');
        const p = document.createElement('p');
        p.append(richText('μ = cos θ<sub>v</sub>, E<sub>avg</sub> = 0.05, theta_o_deg<img src=x onerror="window.bad=1">'));
        const layout = { title: { text: 'Albedo — GGX α=0.3<br><sub>max of |E − E<sub>ref</sub>|</sub>' } };
        return JSON.stringify({ html: p.innerHTML, imgs: p.querySelectorAll('img').length,
            plain: plainIndex('F − F<sub>exact</sub> (right axis)'), title: titleText(layout),
            kept: fitLayout(layout, { keepTitle: true }).title.subtitle.text }); }"""))
    assert out["html"] == "μ = cos θ<sub>v</sub>, E<sub>avg</sub> = 0.05, theta_o_deg", out
    assert out["imgs"] == 0
    assert out["plain"] == "F − F_exact (right axis)"
    assert out["title"] == "Albedo — GGX α=0.3<br><sub>max of |E − E_ref|</sub>"
    assert out["kept"] == "<sub>max of |E − E<sub>ref</sub>|</sub>"     # Plotly draws it in an embed
    assert page_log.problems() == []


def test_comparison_heading_is_not_an_api_description(page, page_log, base_url):
    summary = next(v["summary"] for v in page.request.get(f"{base_url}/api/v1/views").json() if v["name"] == "ndf")
    page.goto("/?pin=ndf:beckmann,alpha:0.2")
    wait_quiet(page)
    text = page.locator('[data-panel="ndf"] h2').inner_text()
    assert summary not in text and "2 models" in text
    assert page_log.problems() == []


def test_panel_list_is_at_the_top(page, page_log):
    page.set_viewport_size({"width": 1400, "height": 900})
    page.goto("/")
    wait_quiet(page)
    assert rect(page, "#show-sphere")["bottom"] < 130
    assert page_log.problems() == []


def test_phone_shows_plots_above_their_controls(page, page_log, shots):
    page.set_viewport_size({"width": 390, "height": 844})
    page.goto("/")
    wait_quiet(page, ids=("plot-lobe",))
    page.evaluate("() => window.scrollTo(0, 0)")
    plot = rect(page, "#plot-lobe")
    assert plot["top"] < 260 and plot["height"] > 200
    # the α slider is on screen with the first plot, below it
    assert inside_viewport(page, "#alpha-slider")
    assert rect(page, "#alpha-slider")["top"] > plot["bottom"] - 80
    assert inside_viewport(page, "#panel-bar")
    assert page.evaluate("() => document.documentElement.scrollWidth <= window.innerWidth")
    page.screenshot(path=str(shots / "screenshot-phone.png"))
    assert page_log.problems() == []


# ---------------------------------------------------------------- exports and embeds

def test_panel_png_is_slide_sized_and_named_after_its_parameters(page, page_log, shots):
    page.goto("/?alpha=0.2&g2=separable&fresnel=dielectric&ior=1.7&theta_i_deg=60")
    wait_quiet(page)
    lobe = page.locator('[data-panel="lobe"]')
    with page.expect_download(timeout=90_000) as dl:
        lobe.locator('button[data-format="png"]').click()
    data = Path(dl.value.path()).read_bytes()
    assert png_size(data) == (3200, 2000)          # 1600 × 1000 at scale 2
    name = dl.value.suggested_filename
    for part in ("alpha=0.2", "g2=separable", "fresnel=dielectric", "ior=1.7", "theta_i_deg=60"):
        assert part in name, name
    (shots / "export-lobe.png").write_bytes(data)
    with page.expect_download(timeout=30_000) as dl:
        page.locator('[data-panel="ndf"] button[data-format="csv"]').click()
    assert "g2=separable" in dl.value.suggested_filename and "theta_i_deg" not in dl.value.suggested_filename
    assert page_log.problems() == []


@pytest.mark.parametrize("size", [(640, 440), (320, 240)])
def test_embed_with_controls_fits_its_frame(page, page_log, size, shots):
    width, height = size
    page.set_viewport_size({"width": width, "height": height})
    page.goto("/embed/g1?controls=1&alpha=0.2")
    page.wait_for_function(EMBED_QUIET, timeout=30_000)
    page.wait_for_function("() => document.querySelector('#embed-controls input')")
    page.wait_for_timeout(300)                      # the plot re-fits after the controls
    assert page.evaluate("() => document.documentElement.scrollHeight <= innerHeight + 1")
    assert inside_viewport(page, "#embed-bar") and inside_viewport(page, '#embed-bar button[data-format="png"]')
    plot = rect(page, "#plot")
    assert plot["height"] >= 0.35 * height
    # the drawn figure is the plot's size: it was fitted after the controls appeared
    drawn = page.evaluate("() => Number(document.querySelector('#plot svg.main-svg').getAttribute('height'))")
    assert abs(drawn - plot["height"]) <= 2
    if width >= 640:
        assert inside_viewport(page, "#plot .legend")
        page.screenshot(path=str(shots / "screenshot-embed.png"))
    assert page_log.problems() == []


def test_page_screenshot(page, page_log, shots):
    page.set_viewport_size({"width": 1400, "height": 900})
    page.goto("/?alpha=0.2&theta_i_deg=50")
    wait_quiet(page)
    page.wait_for_timeout(200)
    page.screenshot(path=str(shots / "screenshot-page.png"))
    assert parse_qs(urlparse(page.url).query)["alpha"] == ["0.2"]
    assert page_log.problems() == []


def test_static_files_cite_nothing_users_do_not_have():
    for path in (ROOT / "static").rglob("*"):
        if path.is_file() and path.suffix in (".js", ".html", ".css"):
            text = path.read_text(encoding="utf-8")
            assert "MATH" + ".md" not in text and "seed 0" not in text, path
