"""While a slider is held, the curves are drawn on a canvas over each plot (static/js/
heldcanvas.js) with the SVG traces hidden; on release the SVG shows them again and the canvas is blank.

What the canvas stands for (the runs of pixel points it was given) is held to Plotly's own
drawing by test_path_writes.py; here, that it paints them: the canvas has ink on every
run it drew and none in the plot area away from them, and the hidden SVG lines are the
ones it replaces."""
from __future__ import annotations

import base64
import re

import pytest

from test_page import wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

PANELS = ("lobe", "ndf", "g1", "albedo")
MOVE_JS = """(v) => { const s = document.getElementById('alpha-slider');
    s.value = String(v); s.dispatchEvent(new Event('input', { bubbles: true })); }"""
GRAB_JS = "() => document.getElementById('alpha-slider').dispatchEvent(new PointerEvent('pointerdown', { bubbles: true }))"
LET_GO = """const s = document.getElementById('alpha-slider');
    s.dispatchEvent(new Event('change', { bubbles: true }));
    s.dispatchEvent(new PointerEvent('pointerup', { bubbles: true }));"""
LET_GO_JS = f"() => {{ {LET_GO} }}"

# A held plot's drawn runs (gd.heldCurves, in each trace layer's pixels) in the SVG's
# pixels, the layers offset as the SVG's translate() say: every point (`all`), and those
# to look for ink at (`sample`: 25 a run, of solid lines, inside the plot area of a
# cartesian plot or the canvas of a polar one, a pixel in from its edges).
POINTS_JS = """(name) => {
  const gd = document.getElementById(`plot-${name}`), fl = gd._fullLayout, xa = fl.xaxis, ya = fl.yaxis;
  const svg = gd.querySelector('.svg-container > svg.main-svg');
  const w = Number.parseFloat(svg.getAttribute('width')), h = Number.parseFloat(svg.getAttribute('height'));
  const inside = (x, y) => xa && ya
    ? x > xa._offset + 1 && x < xa._offset + xa._length - 1 && y > ya._offset + 1 && y < ya._offset + ya._length - 1
    : x > 1 && y > 1 && x < w - 1 && y < h - 1;
  const all = [], sample = [];
  [...gd.querySelectorAll('.scatterlayer g.trace')].forEach((g, i) => {
    let ox = 0, oy = 0;
    for (let n = g; n && n.tagName !== 'svg'; n = n.parentNode) {
      const m = /translate\\(([-\\d.e]+)[ ,]+([-\\d.e]+)\\)/.exec(n.getAttribute('transform') || '');
      if (m) { ox += +m[1]; oy += +m[2]; } }
    const line = g.querySelector('path.js-line')?.style;
    const solid = Number.parseFloat(line?.strokeWidth || '0') > 0 && !(line.strokeDasharray && line.strokeDasharray !== 'none');
    for (const run of gd.heldCurves[i]) for (let k = 0; k < run.length; k++) {
      const p = [run[k][0] + ox, run[k][1] + oy];
      all.push(p);
      if (solid && !(k % Math.max(1, Math.floor(run.length / 25))) && inside(...p)) sample.push(p);
    }
  });
  return { all, sample };
}"""
# On a held plot's canvas (its pixels as the drawing worker holds them: heldPixels): how
# many of the sample points have ink within a pixel, of how many; how much of the plot
# area away from every point (12 px, looked at every 9 px) is blank; and whether the SVG
# traces are hidden.
INK_JS = """async ([name, { all, sample }]) => {
  const gd = document.getElementById(`plot-${name}`);
  const img = await (await import('/static/js/panels/heldcanvas.js')).heldPixels(gd);
  const cv = { width: img.width, height: img.height };
  const svg = gd.querySelector('.svg-container > svg.main-svg');
  const r = cv.width / Number.parseFloat(svg.getAttribute('width'));
  const alphaAt = (x, y) => {
    let best = 0;
    for (let dx = -1; dx <= 1; dx++) for (let dy = -1; dy <= 1; dy++) {
      const u = Math.round((x + dx) * r), v = Math.round((y + dy) * r);
      if (u >= 0 && v >= 0 && u < cv.width && v < cv.height) best = Math.max(best, img.data[4 * (v * cv.width + u) + 3]);
    }
    return best;
  };
  const inked = sample.filter(([x, y]) => alphaAt(x, y) > 0).length;
  const xa = gd._fullLayout.xaxis, ya = gd._fullLayout.yaxis;
  let blank = 0, away = 0;
  if (xa && ya) for (let x = xa._offset + 4; x < xa._offset + xa._length - 4; x += 9)
    for (let y = ya._offset + 4; y < ya._offset + ya._length - 4; y += 9) {
      if (all.some(([u, v]) => Math.abs(u - x) < 12 && Math.abs(v - y) < 12)) continue;
      away++;
      if (alphaAt(x, y) === 0) blank++;
    }
  const hidden = [...gd.querySelectorAll('.scatterlayer g.trace')].every((g) => getComputedStyle(g).visibility === 'hidden');
  return { inked, tried: sample.length, blank, away, hidden };
}"""
# How many of these points of a PNG (base64) are inked (a channel below 200) within a pixel
INKED_PNG_JS = """async ([png, pts]) => {
  const img = new Image(); img.src = 'data:image/png;base64,' + png; await img.decode();
  const c = document.createElement('canvas'); c.width = img.width; c.height = img.height;
  const g = c.getContext('2d'); g.drawImage(img, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data;
  const ink = (x, y) => { for (let dx = -1; dx <= 1; dx++) for (let dy = -1; dy <= 1; dy++) {
    const u = Math.round(x) + dx, v = Math.round(y) + dy, o = 4 * (v * c.width + u);
    if (u >= 0 && v >= 0 && u < c.width && v < c.height && Math.min(d[o], d[o + 1], d[o + 2]) < 200) return true; }
    return false; };
  return pts.filter(([x, y]) => ink(x, y)).length;
}"""
SHOWN_JS = """async (name) => { const gd = document.getElementById(`plot-${name}`);
  const img = await (await import('/static/js/panels/heldcanvas.js')).heldPixels(gd);
  const ink = !!img && img.data.some((v, i) => i % 4 === 3 && v > 0);
  return { held: gd.classList.contains('held-canvas'), canvas: ink,
           traces: [...gd.querySelectorAll('.scatterlayer g.trace')].every((g) => getComputedStyle(g).visibility === 'visible') }; }"""


def test_a_held_slider_draws_the_curves_on_a_canvas_and_gives_them_back_on_release(page, page_log):
    page.goto("/?alpha=0.3")
    wait_quiet(page)
    page.evaluate(GRAB_JS)
    for v in range(620, 560, -6):
        page.evaluate(MOVE_JS, v)
        page.wait_for_timeout(40)
    wait_quiet(page)
    # held still for longer than the page's idle sync (panels.js SYNC_IDLE_MS, 1.5 s): the
    # canvases stay (Plotly redrawing the SVG now would be in the way of the next move)
    page.wait_for_timeout(2000)
    for name in PANELS:
        assert page.evaluate("(n) => document.getElementById(`plot-${n}`).classList.contains('held-canvas')", name), name
        ink = page.evaluate(INK_JS, [name, page.evaluate(POINTS_JS, name)])
        assert ink["hidden"], (name, ink)
        assert ink["tried"] >= 10 and ink["inked"] == ink["tried"], (name, ink)
        if name in ("ndf", "g1"):  # lines only (the lobe is polar, the albedo has a band and bars)
            assert ink["away"] >= 20 and ink["blank"] == ink["away"], (name, ink)
    # and on the screen: with the SVG lines hidden, the ink at the NDF's points is the canvas's
    points = page.evaluate(POINTS_JS, "ndf")["sample"]
    png = base64.b64encode(page.locator("#plot-ndf").screenshot()).decode()
    assert len(points) >= 10 and page.evaluate(INKED_PNG_JS, [png, points]) == len(points)
    page.evaluate(LET_GO_JS)
    wait_quiet(page)
    for name in PANELS:
        assert page.evaluate(SHOWN_JS, name) == {"held": False, "canvas": False, "traces": True}, name
    assert page_log.problems() == []


def test_a_heading_whose_numbers_moved_is_rewritten_in_place(page):
    """A panel's heading (GGX α=0.0425, θ<sub>i</sub>=45°) is redrawn with each held frame:
    the same markup keeps its nodes and only their text changes (static/js/base/dom.js
    replaceText); other markup replaces them. Either way it reads as richText renders it."""
    page.goto("/")
    got = page.evaluate("""async () => {
      const { richText, replaceText } = await import('/static/js/base/dom.js');
      const h = document.createElement('span');
      const say = (t) => { replaceText(h, richText(t)); return [h.textContent, h.innerHTML]; };
      const first = say('GGX α=0.0425, θ_i=45°');
      const nodes = [...h.childNodes];
      const moved = say('GGX α=0.0431, θ_i=45°');
      const kept = nodes.length === h.childNodes.length && nodes.every((n, i) => n === h.childNodes[i]);
      const other = say('GGX α=0.05, comparing vary = 1, 2');
      const fresh = document.createElement('span'); fresh.append(richText('GGX α=0.05, comparing vary = 1, 2'));
      return { first, moved, kept, other, fresh: fresh.innerHTML, replaced: !nodes.some((n) => n.parentNode === h) };
    }""")
    assert got["first"] == ["GGX α=0.0425, θi=45°", "GGX α=0.0425, θ<sub>i</sub>=45°"]
    assert got["moved"] == ["GGX α=0.0431, θi=45°", "GGX α=0.0431, θ<sub>i</sub>=45°"]
    assert got["kept"]
    assert got["other"][1] == got["fresh"] and got["replaced"]


def test_readouts_follow_a_held_slider_a_few_times_a_second_and_at_once_when_let_go(page):
    """A panel's heading and legend numbers (static/js/panels/readouts.js): while a slider is
    held, a write waits until READOUT_MS have passed since the last one and the newest
    waiting value is the one written; not held, or let go, everything is written at once;
    a write dropped (Plotly drew the legend meanwhile) is never made."""
    page.goto("/")
    got = page.evaluate("""async () => {
      const { Readouts, READOUT_MS } = await import('/static/js/panels/readouts.js');
      const r = new Readouts(), log = [];
      const sleep = (ms) => new Promise((f) => setTimeout(f, ms));
      const t0 = performance.now(), at = () => performance.now() - t0;
      for (let k = 0; k < 8; k++) {
        const shown = at();
        r.show('sub', () => log.push(['sub', k, at(), shown]), true);
        await sleep(20);
      }
      await sleep(READOUT_MS + 50);
      const burst = log.slice();
      r.show('sub', () => log.push(['sub', 'held', at()]), true);
      r.show('legend', () => log.push(['legend', 'dropped', at()]), true);
      r.drop('legend');
      r.flush();                                   // let go
      r.show('sub', () => log.push(['sub', 'free', at()]), false);
      return { READOUT_MS, burst, log };
    }""")
    ms, burst, log = got["READOUT_MS"], got["burst"], got["log"]
    assert 100 <= ms <= 500                                      # a few times a second
    assert burst[0][1] == 0 and burst[0][2] - burst[0][3] < 5   # the first at once
    assert burst[-1][1] == 7                                     # the newest last
    assert len(burst) < 8                                        # the rest waited: some never written
    ks = [e[1] for e in burst]
    assert ks == sorted(ks)
    gaps = [b[2] - a[2] for a, b in zip(burst, burst[1:])]
    assert all(g >= ms - 5 for g in gaps), gaps                 # not before their time (timer slack)
    assert [e[:2] for e in log[len(burst):]] == [["sub", "held"], ["sub", "free"]]   # flushed; dropped never written


def test_a_held_drag_ends_with_the_headings_saying_what_is_drawn(page):
    """The readouts lag a held drag by at most READOUT_MS and are exact once it is let
    go: each heading names the α the panel shows, and letting go writes what waits at
    once (a readout made to wait is written in the same task as the release)."""
    page.goto("/?alpha=0.3")
    wait_quiet(page)
    page.evaluate(GRAB_JS)
    for v in range(620, 500, -4):                  # 30 moves, 15 ms apart: faster than the readouts
        page.evaluate(MOVE_JS, v)
        page.wait_for_timeout(15)
    probe = page.evaluate(f"""() => {{
      const r = window.__brdf.panel('ndf').readouts;
      r.flush();                                   // just written: the next one waits
      let wrote = false;
      r.show('probe', () => {{ wrote = true; }}, true);
      const waited = !wrote;
      {LET_GO}
      return {{ waited, wrote }};
    }}""")
    assert probe == {"waited": True, "wrote": True}
    wait_quiet(page)
    alpha = page.evaluate("() => Number(document.getElementById('alpha').value)")
    for name in PANELS:
        sub = page.locator(f'[data-panel="{name}"] h2 .sub').inner_text()
        m = re.search(r"α=([0-9.e-]+)", sub.replace(" ", ""))
        assert m and abs(float(m.group(1)) / alpha - 1) < 1e-3, (name, sub, alpha)
    # and the albedo legend names what its traces are now (E_avg moved with α)
    legend = page.evaluate("""() => { const gd = document.getElementById('plot-albedo');
        return { drawn: [...gd.querySelectorAll('.legend .legendtext')].map((t) => t.textContent),
                 names: gd.data.map((t) => t.name) }; }""")
    plain = lambda t: re.sub(r"<[^>]+>", "", t).replace("\u200b", "")   # Plotly's sub as text  # noqa: E731
    avg = [plain(t) for t in legend["drawn"] if "avg" in t]
    assert avg and all(t in map(plain, legend["names"]) for t in avg), legend


def test_a_heading_that_wraps_while_held_leaves_its_plot_as_it_is(page):
    """A readout whose text wraps to a second line in the drag (the G₁ heading at some α,
    the panel 473 px wide) resized the plot below it: a full Plotly redraw in the middle
    of the drag, and the held canvas dropped. While held, a heading keeps its height."""
    page.goto("/?alpha=0.3")
    wait_quiet(page)
    plot_height = "() => document.getElementById('plot-g1').getBoundingClientRect().height"
    page.evaluate(GRAB_JS)
    page.evaluate(MOVE_JS, 600)
    page.wait_for_function("() => document.getElementById('plot-g1').classList.contains('held-canvas')", timeout=20_000)
    before = page.evaluate(plot_height)
    page.evaluate("() => { document.querySelector('#h-g1 .sub').textContent = ' a readout long enough to wrap'.repeat(6); }")
    page.wait_for_timeout(500)                     # a ResizeObserver's callback comes in the next frame
    assert page.evaluate(plot_height) == before
    assert page.evaluate("() => document.getElementById('plot-g1').classList.contains('held-canvas')")
    page.evaluate(LET_GO_JS)
    wait_quiet(page)
    assert page.evaluate("() => document.getElementById('h-g1').style.height") == ""   # free again


# Marks each animation frame's callbacks and what they run before their task ends: the
# flag is set for each callback and cleared only after ten rounds of microtasks, so a write
# chained to the frame's promise (the microtasks run after each callback) sees it set,
# and one in a task of its own sees it clear. Each held redraw (the page's draw event)
# records whether it ran inside the frame's task.
FRAME_TASK_JS = """() => {
  const raf = window.requestAnimationFrame.bind(window);
  window.__inFrame = false;
  window.__heldDraws = [];
  window.requestAnimationFrame = (cb) => raf((ts) => {
    window.__inFrame = true;
    cb(ts);
    let rounds = 10;
    const hop = () => { if (--rounds) queueMicrotask(hop); else window.__inFrame = false; };
    queueMicrotask(hop);
  });
  for (const d of document.querySelectorAll('.js-plotly-plot')) {
    d.addEventListener(window.__brdf.drawEvent, () => {
      if (!d.classList.contains('held-canvas')) return;
      // a draw that finds another's mark drew in the same task as it (the mark is cleared,
      // as the frame's flag, after ten rounds of microtasks: before the task ends)
      const shared = !!window.__drawMark;
      window.__heldDraws.push([d.id, window.__inFrame, shared]);
      if (shared) return;
      window.__drawMark = true;
      let rounds = 10;
      const hop = () => { if (--rounds) queueMicrotask(hop); else window.__drawMark = false; };
      queueMicrotask(hop);
    });
  }
}"""


def test_a_held_frame_writes_each_panel_in_a_task_of_its_own_after_the_frame(page):
    """A held redraw's writes (four panels' points computed and posted, 2-5 ms) run after
    the animation frame, one task a panel, not inside the frame's task with its paint and
    commit: an input event due meanwhile runs between them, not after all of it
    (BENCHMARKS.md §5, thirteenth session)."""
    page.goto("/?alpha=0.3")
    wait_quiet(page)
    page.evaluate(FRAME_TASK_JS)
    page.evaluate(GRAB_JS)
    for v in range(620, 500, -6):
        page.evaluate(MOVE_JS, v)
        page.wait_for_timeout(40)
    wait_quiet(page)
    draws = page.evaluate("() => window.__heldDraws")
    page.evaluate(LET_GO_JS)
    wait_quiet(page)
    assert {d for d, _, _ in draws} == {f"plot-{n}" for n in PANELS}, draws
    assert len(draws) >= 20 and not any(inside for _, inside, _ in draws), draws
    assert not any(shared for _, _, shared in draws), draws      # one task a panel
