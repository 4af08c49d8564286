"""The panels' figure GETs of one change go out as one POST /api/v1/batch (static/js/
batch.js, app/api/routes_batch.py): each answer is what its GET answers, each panel draws
its own, one request a move; the URL waits for a held slider's release."""
from __future__ import annotations

import base64
import json
from urllib.parse import urlparse

import numpy as np
import pytest

from test_page import wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

PANELS = ("lobe", "ndf", "g1", "albedo")


def numbers(a) -> list:
    """A trace array as the API sends it (a list, or Plotly's {dtype, bdata})."""
    if isinstance(a, dict) and "bdata" in a:
        return np.frombuffer(base64.b64decode(a["bdata"]), dtype=np.dtype(a["dtype"])).astype(float).tolist()
    if isinstance(a, dict):           # a typed array as the page holds it, serialised by index
        return [float(a[k]) for k in sorted(a, key=int)]
    return [float("nan") if v is None else v for v in a]


#: how far a batch's answer may differ from its GET's: the same model may be answered by its
#: compiled loops in one and by numpy in the other (whichever is ready when each arrives), and
#: the two agree to 1e-12 relative (tests/kernels/test_compiled_matches_numpy.py)
PATHS_AGREE = 1e-12


def assert_same_answer(a, b, where: str) -> None:
    """``a`` and ``b`` the same JSON: the same keys, lists and strings, numbers (and typed
    arrays) equal to PATHS_AGREE relative."""
    if isinstance(a, dict) and "bdata" in a or isinstance(b, dict) and "bdata" in b:
        np.testing.assert_allclose(numbers(a), numbers(b), rtol=PATHS_AGREE, atol=0, err_msg=where)
    elif isinstance(a, dict):
        assert isinstance(b, dict) and a.keys() == b.keys(), where
        for k in a:
            assert_same_answer(a[k], b[k], f"{where}.{k}")
    elif isinstance(a, list):
        assert isinstance(b, list) and len(a) == len(b), where
        for i, (x, y) in enumerate(zip(a, b)):
            assert_same_answer(x, y, f"{where}[{i}]")
    elif isinstance(a, float) or isinstance(b, float):
        assert b == pytest.approx(a, rel=PATHS_AGREE, abs=0), where
    else:
        assert a == b, where


MOVE_JS = """(v) => { const s = document.getElementById('alpha-slider');
    s.value = String(v); s.dispatchEvent(new Event('input', { bubbles: true })); }"""


def test_batch_answers_each_figure_as_its_get(page, base_url):
    urls = ["/api/v1/figures/ndf?alpha=0.17", "/api/v1/figures/lobe?alpha=0.17&theta_i_deg=30",
            "/api/v1/figures/g1?alpha=7", "/api/v1/figures/albedo?alpha=0.17&method=auto"]
    res = page.request.post(f"{base_url}/api/v1/batch", data=json.dumps({"requests": urls}),
                            headers={"Content-Type": "application/json"})
    assert res.ok
    answers = res.json()["responses"]
    assert len(answers) == len(urls)
    for u, a in zip(urls, answers):
        get = page.request.get(base_url + u)
        assert a["status"] == get.status, u
        assert_same_answer(a["body"], get.json(), u)
    assert answers[2]["status"] == 422 and "alpha" in json.dumps(answers[2]["body"])
    # a batch answers the figures' GETs, nothing else
    for bad in (["/api/v1/health"], ["http://example.org/api/v1/figures/ndf"], [], ["/api/v1/batch"]):
        r = page.request.post(f"{base_url}/api/v1/batch", data=json.dumps({"requests": bad}),
                              headers={"Content-Type": "application/json"})
        assert r.status == 422, bad


def test_a_move_asks_once_for_every_panel_and_each_draws_its_answer(page, page_log, base_url):
    page.goto("/?theta_i_deg=50")
    wait_quiet(page)
    n_before = len(page_log.requests)
    page.evaluate(MOVE_JS, 612)
    wait_quiet(page)
    sent = page_log.requests[n_before:]
    posts = [u for u in sent if urlparse(u).path == "/api/v1/batch"]
    assert len(posts) == 1, sent
    # (conftest logs each GET a batch stands for) every panel's figure, once
    for name in PANELS:
        assert sum(urlparse(u).path == f"/api/v1/figures/{name}" for u in sent) == 1, (name, sent)
    # no GET of its own reached the server: the GETs logged are the batch's, besides the
    # GPU panel's one request for the moved model's shader (js/gpu/: it draws in WebGL2)
    code = [u for u in sent if urlparse(u).path == "/api/v1/code"]
    assert len(code) <= 1, code
    assert len(sent) - len(code) == 1 + len(PANELS), sent
    for name in PANELS:
        url = page.evaluate("(n) => window.__brdf.url(n)", name)
        want = page.request.get(base_url + url).json()["data"]
        shown = page.evaluate("""(n) => JSON.parse(JSON.stringify(document.getElementById(`plot-${n}`).data,
            (k, v) => (ArrayBuffer.isView(v) ? Array.from(v) : v)))""", name)
        assert [t.get("name") for t in shown] == [t.get("name") for t in want], name
        for a, b in zip(shown, want):
            for key in ("x", "y", "r", "theta"):
                if key in b:
                    assert numbers(a[key]) == pytest.approx(numbers(b[key]), nan_ok=True), (name, key)
    assert page_log.problems() == []


def test_a_held_slider_moved_back_draws_from_memory_and_writes_the_url_on_release(page, page_log):
    page.goto("/")
    wait_quiet(page)
    start = page.evaluate("() => document.getElementById('alpha-slider').value")
    url_before = page.url
    page.evaluate("""() => { const s = document.getElementById('alpha-slider');
        s.dispatchEvent(new PointerEvent('pointerdown', { bubbles: true })); }""")
    page.evaluate(MOVE_JS, 640)
    wait_quiet(page)
    page.evaluate(MOVE_JS, int(start))
    n_before = len(page_log.requests)
    wait_quiet(page)
    # held, back where it started: the figures answered already are drawn from memory
    assert not [u for u in page_log.requests[n_before:] if "/api/v1/" in u]
    assert page.evaluate("() => window.__brdf.panels().every((p) => !p.visible || p.current)")
    # the panels follow the held slider; the URL waits for the release
    page.evaluate(MOVE_JS, 640)
    wait_quiet(page)
    alpha = page.evaluate("() => window.__brdf.state.alpha")
    assert page.evaluate("() => window.__brdf.panels().every((p) => !p.visible || p.current)")
    assert page.url == url_before
    page.evaluate("""() => { const s = document.getElementById('alpha-slider');
        s.dispatchEvent(new Event('change', { bubbles: true }));
        s.dispatchEvent(new PointerEvent('pointerup', { bubbles: true })); }""")
    wait_quiet(page)
    assert f"alpha={alpha}" in page.url
    assert page_log.problems() == []


def test_a_held_slider_asks_at_most_every_33_ms_and_ends_on_the_newest_state(page, page_log):
    """While a slider is held, a move every 4 ms sends a batch at most every 33 ms
    (static/js/net/scheduler.js HELD_FRAME_MS, from the call that asked; the POST leaves at
    the end of that task, a few ms later or sooner; unpaced, the second went out 4 ms
    after the first), and the panels end drawing the last position."""
    page.goto("/")
    wait_quiet(page)
    page.evaluate("() => performance.clearResourceTimings()")
    page.evaluate("""async () => { const s = document.getElementById('alpha-slider');
        s.dispatchEvent(new PointerEvent('pointerdown', { bubbles: true }));
        for (let k = 0; k < 75; k++) {
          s.value = String(300 + 4 * k);
          s.dispatchEvent(new Event('input', { bubbles: true }));
          await new Promise((r) => setTimeout(r, 4));
        } }""")
    wait_quiet(page)
    starts = page.evaluate("""() => performance.getEntriesByType('resource')
        .filter((e) => e.name.endsWith('/api/v1/batch')).map((e) => e.startTime)""")
    assert len(starts) >= 3, starts
    gaps = [b - a for a, b in zip(starts, starts[1:])]
    assert min(gaps) >= 20, gaps
    assert page.evaluate("() => document.getElementById('alpha-slider').value") == str(300 + 4 * 74)
    assert page.evaluate("() => window.__brdf.panels().every((p) => !p.visible || p.current)")
    assert page_log.problems() == []


RANGES_JS = """() => Object.fromEntries(['lobe', 'ndf', 'g1', 'albedo'].map((n) => {
    const l = document.getElementById(`plot-${n}`).layout;
    const axes = Object.keys(l).filter((k) => /^[xy]axis\\d*$/.test(k)).sort();
    return [n, [...axes.map((k) => [k, l[k].range, l[k].dtick]),
                ['polar', l.polar?.radialaxis?.range]]]; }))"""


def test_a_drag_draws_the_curves_on_their_charts_and_let_go_leaves_what_a_fresh_page_draws(page, base_url):
    """The curve panels are drawn by their charts, through a drag and after it: Plotly
    is not called for them (one renderer per panel). Let go, every panel's figure (its
    axes' ranges and ticks) is the server's, as a fresh page of the same URL draws it."""
    page.goto("/")
    wait_quiet(page)
    page.evaluate("""() => { window.__reacts = []; const react = Plotly.react;
        Plotly.react = (gd, ...a) => { window.__reacts.push(gd.id); return react(gd, ...a); }; }""")
    start = int(page.evaluate("() => document.getElementById('alpha-slider').value"))
    page.evaluate("""async (start) => { const s = document.getElementById('alpha-slider');
        s.dispatchEvent(new PointerEvent('pointerdown', { bubbles: true }));
        for (let k = 1; k <= 60; k++) {
          s.value = String(start - 3 * k);
          s.dispatchEvent(new Event('input', { bubbles: true }));
          await new Promise((r) => setTimeout(r, 17));
        } }""", start)
    wait_quiet(page)
    held_reacts = page.evaluate("() => window.__reacts")
    # the log axes' panels (the albedo may change its traces: the table's name, a method)
    page.evaluate("""() => { const s = document.getElementById('alpha-slider');
        s.dispatchEvent(new Event('change', { bubbles: true }));
        s.dispatchEvent(new PointerEvent('pointerup', { bubbles: true })); }""")
    wait_quiet(page)
    assert not {"plot-lobe", "plot-ndf", "plot-g1", "plot-albedo"} & set(held_reacts + page.evaluate("() => window.__reacts")), held_reacts
    dragged = page.evaluate(RANGES_JS)
    fresh = page.context.new_page()
    fresh.goto(page.url)
    wait_quiet(fresh)
    assert dragged == fresh.evaluate(RANGES_JS)
    fresh.close()
