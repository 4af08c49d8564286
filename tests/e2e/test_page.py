"""The page in a real browser: URL state, linked controls, coalesced fetching, errors.

Run: pytest -m e2e tests/e2e -s   (-s shows the slider-to-redraw timing)
"""
from __future__ import annotations

import json
import statistics
from pathlib import Path
from urllib.parse import parse_qs, urlparse

import pytest

pytestmark = pytest.mark.e2e

PANELS = ("plot-lobe", "plot-ndf", "plot-g1", "plot-albedo")

QUIET_JS = """(ids) => window.__brdf && window.__brdf.pending() === 0
    && ids.every((id) => { const d = document.getElementById(id); return d && d.data && d.layout; })"""
# a panel is fetched only near the viewport: each is scrolled into view in turn and
# waited for until it shows the current state
CURRENT_JS = """(id) => { const d = document.getElementById(id);
    if (d) d.scrollIntoView({ block: 'nearest' });
    const p = window.__brdf && window.__brdf.panels().find((x) => 'plot-' + x.name === id);
    return !!p && window.__brdf.pending() === 0 && !!(d && d.layout) && (p.current || !!p.error); }"""
LOBE_R_EXPR = "JSON.stringify(document.getElementById('plot-lobe').data[0].r)"
LOBE_R_JS = f"() => {LOBE_R_EXPR}"


def wait_quiet(page, ids=PANELS, timeout=20_000):
    for i in ids:
        page.wait_for_function(CURRENT_JS, arg=i, timeout=timeout)
    page.wait_for_function(QUIET_JS, arg=list(ids), timeout=timeout)


def query(page) -> dict[str, str]:
    return {k: v[-1] for k, v in parse_qs(urlparse(page.url).query).items()}


def move_slider(page, slider_id: str, value: float) -> None:
    page.evaluate("""([id, v]) => { const s = document.getElementById(id);
        s.value = String(v); s.dispatchEvent(new Event('input', {bubbles: true})); }""",
                  [slider_id, value])


def api_requests(log, endpoint: str) -> list[dict[str, str]]:
    out = []
    for url in log.requests:
        u = urlparse(url)
        if u.path == f"/api/v1/figures/{endpoint}":
            out.append({k: v[-1] for k, v in parse_qs(u.query).items()})
    return out


def test_url_state_slider_redraw_screenshot_and_timing(page, page_log, capsys):
    page.goto("/?ndf=beckmann&alpha=0.2&theta_i_deg=60")

    # 1. the controls show the state of the URL
    page.wait_for_function("() => document.querySelector('#ndf option')")
    assert page.input_value("#ndf") == "beckmann"
    assert page.input_value("#alpha") == "0.2"
    assert page.input_value("#theta_i") == "60"
    assert not page.is_checked("#anisotropic")
    assert page.evaluate("() => document.getElementById('alpha_y').disabled")

    # 2. the lobe (and the other panels) drew
    wait_quiet(page)
    before = page.evaluate(LOBE_R_JS)
    assert before and before != "null"
    lobe_query = api_requests(page_log, "lobe")[-1]
    assert lobe_query["ndf"] == "beckmann" and float(lobe_query["alpha"]) == 0.2
    assert float(lobe_query["theta_i_deg"]) == 60
    assert "alpha_y" not in lobe_query      # isotropic: α_y is never sent

    # 3. the α slider redraws the lobe and rewrites the URL
    move_slider(page, "alpha-slider", 250)
    page.wait_for_function(f"(old) => window.__brdf.pending() === 0 && {LOBE_R_EXPR} !== old",
                           arg=before)
    new_alpha = page.evaluate("() => window.__brdf.state.alpha")
    assert new_alpha != 0.2 and 1e-4 <= new_alpha <= 1
    assert page.input_value("#alpha") == str(page.evaluate("() => String(window.__brdf.state.alpha)"))
    q = query(page)
    assert float(q["alpha"]) == new_alpha
    assert q["ndf"] == "beckmann" and float(q["theta_i_deg"]) == 60

    # typing into the number box moves the slider and the URL too
    page.fill("#alpha", "0.05")
    page.wait_for_function("() => window.__brdf.pending() === 0 && window.__brdf.state.alpha === 0.05")
    assert query(page)["alpha"] == "0.05"
    slider_pos = float(page.input_value("#alpha-slider"))
    page.fill("#alpha", "0.3")
    page.wait_for_function("() => window.__brdf.state.alpha === 0.3")
    assert float(page.input_value("#alpha-slider")) > slider_pos
    wait_quiet(page)

    # 5. (the page's screenshot: test_page_modules.py, at 1400 × 900)
    # 6. slider move → the lobe redrawn (the page's draw event), 20 times
    positions = [300 + 20 * i for i in range(20)]   # 20 distinct α values
    times = page.evaluate("""async (positions) => {
        const gd = document.getElementById('plot-lobe');
        const slider = document.getElementById('alpha-slider');
        const out = [];
        for (const pos of positions) {
          const drawn = new Promise((resolve) => {
            const timer = setTimeout(() => resolve(NaN), 10000);
            gd.addEventListener(window.__brdf.drawEvent, () => { clearTimeout(timer); resolve(performance.now()); },
                                { once: true });
          });
          const t0 = performance.now();
          slider.value = String(pos);
          slider.dispatchEvent(new Event('input', {bubbles: true}));
          const t1 = await drawn;
          out.push(t1 - t0);
          await new Promise((r) => { const w = () => window.__brdf.pending() ? setTimeout(w, 5) : r(); w(); });
        }
        return out;
    }""", positions)
    assert len(times) == 20 and all(t == t for t in times), f"a move did not redraw: {times}"
    with capsys.disabled():
        print(f"\nslider→redraw (plot-lobe plotly_afterplot), 20 moves: median {statistics.median(times):.1f} ms,"
              f" min {min(times):.1f}, max {max(times):.1f}")

    # 4. nothing went wrong in the page
    wait_quiet(page)
    assert page_log.problems() == []


def test_url_restores_exactly(page, page_log):
    page.goto("/")
    wait_quiet(page)
    page.check("#anisotropic")
    page.fill("#alpha_y", "0.0123")
    page.select_option("#fresnel", "none")
    page.fill("#kd", "0.25")
    page.fill("#phi_i", "-30")
    page.check("#log")
    page.check("#cosine")
    wait_quiet(page)
    state = page.evaluate("() => JSON.stringify(window.__brdf.state)")
    q = query(page)
    assert q["alpha_y"] == "0.0123" and q["fresnel"] == "none" and q["log"] == "true"
    assert "f0" not in q and "f90" not in q and "alpha" not in q   # defaults stay out

    lobe = api_requests(page_log, "lobe")[-1]
    assert lobe["alpha_y"] == "0.0123" and lobe["cosine"] == "true" and lobe["log"] == "true"
    assert "f0" not in lobe and "f90" not in lobe      # Schlick's params only with Schlick
    assert api_requests(page_log, "ndf")[-1]["phi_deg"] == "-30"   # anisotropic slice

    page.goto(page.url)
    wait_quiet(page)
    assert page.evaluate("() => JSON.stringify(window.__brdf.state)") == state
    assert page.is_checked("#anisotropic") and page.is_checked("#log") and page.is_checked("#cosine")
    assert page.input_value("#alpha_y") == "0.0123"
    assert page.input_value("#fresnel") == "none"
    assert page.is_hidden("#f0")

    page.select_option("#fresnel", "schlick")
    page.fill("#f0", "0.9")
    wait_quiet(page)
    assert api_requests(page_log, "lobe")[-1]["f0"] == "0.9"
    assert page_log.problems() == []


def test_fast_changes_are_coalesced(page, page_log):
    page.goto("/")
    wait_quiet(page)
    n0 = len(api_requests(page_log, "albedo"))
    # 40 slider moves in one task: at most two requests in flight per panel (scheduler.js
    # MAX_IN_FLIGHT), the newest state fetched when one lands, and what is drawn is the
    # final state.
    page.evaluate("""() => { const s = document.getElementById('alpha-slider');
        for (let i = 0; i < 40; i++) { s.value = String(200 + 10 * i);
          s.dispatchEvent(new Event('input', {bubbles: true})); } }""")
    wait_quiet(page)
    albedo = api_requests(page_log, "albedo")[n0:]
    assert 1 <= len(albedo) <= 3, albedo
    final_alpha = page.evaluate("() => window.__brdf.state.alpha")
    assert float(albedo[-1]["alpha"]) == final_alpha
    assert float(api_requests(page_log, "lobe")[-1]["alpha"]) == final_alpha
    # the hidden 3-D panel is never fetched ... until it is shown
    assert api_requests(page_log, "lobe3d") == []
    page.check("#show-lobe3d")
    wait_quiet(page, ids=(*PANELS, "plot-lobe3d"))
    assert len(api_requests(page_log, "lobe3d")) == 1
    assert page_log.problems() == []


def test_embed_hides_controls(page, page_log):
    page.goto("/?embed=1&alpha=0.1")
    wait_quiet(page)
    assert page.is_hidden("#controls")
    assert page.is_hidden("#log")
    for pid in PANELS:
        assert page.is_visible(f"#{pid}")
    assert query(page).get("embed") == "1"
    assert page_log.problems() == []


def test_bad_url_values_are_clamped_with_a_notice(page, page_log):
    page.goto("/?alpha=5&ndf=nonsense&theta_i_deg=abc")
    wait_quiet(page)
    assert page.input_value("#alpha") == "1"
    assert page.input_value("#ndf") == "ggx"
    assert page.input_value("#theta_i") == "45"
    notice = page.inner_text("#notice")
    assert "alpha=5" in notice and "[0.0001, 1]" in notice
    assert "ndf=nonsense" in notice and "theta_i_deg=abc" in notice
    assert query(page).get("alpha") == "1"
    # an out-of-range value typed into a box is flagged, not sent
    page.fill("#alpha", "7")
    page.wait_for_selector("#alpha[aria-invalid=true]")
    assert "[0.0001, 1]" in page.inner_text("#alpha-msg")
    assert page.evaluate("() => window.__brdf.state.alpha") == 1
    page.press("#alpha", "Tab")                 # leaving the box restores the value
    assert page.input_value("#alpha") == "1"
    assert page.get_attribute("#alpha", "aria-invalid") is None
    assert page_log.problems() == []


def test_api_error_is_shown_in_the_panel(page, page_log):
    detail = {"detail": [{"loc": ["query", "alpha"], "msg": "alpha: too rough for this test",
                          "type": "value_error"}]}
    page.route("**/api/v1/figures/g1?*", lambda route: route.fulfill(
        status=422, content_type="application/json", body=json.dumps(detail)))

    def batch_with_g1_refused(route):
        # the panels' GETs of one change go out as one POST /api/v1/batch: its g1 answer
        # is the 422 above, the others the server's
        sent = json.loads(route.request.post_data)["requests"]
        answer = route.fetch().json()
        for u, r in zip(sent, answer["responses"]):
            if u.startswith("/api/v1/figures/g1?"):
                r.update(status=422, cache="no-store", body=detail)
        route.fulfill(status=200, content_type="application/json", body=json.dumps(answer))
    page.route("**/api/v1/batch", batch_with_g1_refused)
    page.goto("/")
    wait_quiet(page, ids=("plot-lobe", "plot-ndf", "plot-albedo"))
    status = page.locator('[data-panel="g1"] .panel-status')
    assert "too rough for this test" in status.inner_text()
    assert "too rough for this test" in page.inner_text("#error-line")
    assert page_log.page_errors == []
    # the other panels are unaffected; the only console error is the browser's own
    # report of the 422 response
    assert all("422" in e for e in page_log.console_errors)


def test_slow_panel_says_loading(page, page_log):
    # albedo answers late (900 ms; with the panels it is asked with, when they go out as
    # one POST /api/v1/batch): its panel says "loading…" after 300 ms
    page.add_init_script("""(() => { const f = window.fetch;
        window.fetch = (u, o) => (String(u) + String(o?.body || '')).includes('/figures/albedo')
          ? new Promise((r) => setTimeout(r, 900)).then(() => f(u, o)) : f(u, o); })()""")
    # what the status said, recorded in the page as it changes (a poll from the test can
    # miss a status that a loaded machine shows for less than the poll's period)
    page.add_init_script("""document.addEventListener('DOMContentLoaded', () => {
        window.__albedoStatus = [];
        new MutationObserver(() => {
          const s = document.querySelector('[data-panel="albedo"] .panel-status');
          if (s && s.classList.contains('loading')) window.__albedoStatus.push(s.textContent);
        }).observe(document.body, { subtree: true, attributes: true, childList: true, characterData: true });
      })""")
    page.goto("/")
    status = page.locator('[data-panel="albedo"] .panel-status')
    page.wait_for_function("() => (window.__albedoStatus || []).length > 0", timeout=30_000)
    assert page.evaluate("() => window.__albedoStatus")[0] == "loading…"
    wait_quiet(page)
    assert status.inner_text() == ""
    assert page_log.problems() == []


def test_narrow_window_stacks_panels(page, page_log):
    page.set_viewport_size({"width": 700, "height": 900})
    page.goto("/")
    wait_quiet(page)
    boxes = [page.locator(f"#{pid}").bounding_box() for pid in PANELS]
    assert len({round(b["x"]) for b in boxes}) == 1          # one column
    assert all(b["width"] > 500 and b["height"] > 250 for b in boxes)
    assert page.evaluate("() => document.documentElement.scrollWidth <= window.innerWidth")
    assert page_log.problems() == []


# For every visible slider and slider's number box (sliders.js: the sidebar's and the
# embeds' rows): [type, id, ok as a layout root, its height, the height the same element
# takes unconstrained (a copy beside it, its fixed height and containment undone
# inline), its text fits]
SLIDER_BOXES_JS = """() => [...document.querySelectorAll(
    'input[type=range], .param-head input[type=number], .embed-param input[type=number]')]
  .filter((e) => e.offsetParent !== null).map((e) => {
    const cs = getComputedStyle(e);
    const root = cs.contain.includes('size') && cs.contain.includes('layout')
      && getComputedStyle(e.parentElement).display === 'block';
    const copy = e.cloneNode();
    copy.removeAttribute('id');
    copy.style.height = 'auto';
    copy.style.contain = 'none';
    e.after(copy);
    const natural = copy.getBoundingClientRect().height;
    copy.remove();
    return [e.type, e.id, root, e.getBoundingClientRect().height, natural, e.scrollHeight <= e.clientHeight];
  })"""


@pytest.mark.parametrize("path", ["/", "/embed/ndf?controls=1"])
def test_slider_and_number_box_lay_out_alone_at_their_natural_size(page, page_log, path):
    """Each slider and number box is its own layout root (style.css: a moved thumb or a
    rewritten number lays out that control alone, not the page: BENCHMARKS.md §5). Size
    containment needs a fixed height: it must be the one the browser gives the control
    unconstrained, in the explorer's sidebar and in an embed's smaller type."""
    page.goto(path)
    page.wait_for_function("() => window.__brdf ? window.__brdf.pending() === 0 : !!document.querySelector('.field')")
    boxes = page.evaluate(SLIDER_BOXES_JS)
    assert {kind for kind, *_ in boxes} == {"range", "number"}, boxes
    for _, ident, root, height, natural, fits in boxes:
        assert root, f"{ident} is not a layout root"
        assert abs(height - natural) <= 1.0, (ident, height, natural)
        assert fits, f"{ident}: its text overflows its fixed height"
    assert page_log.problems() == []
