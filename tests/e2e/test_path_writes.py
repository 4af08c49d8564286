"""A slider move's data-only redraw (static/js/panels/svgpaths.js writes the traces' SVG paths
itself) draws what Plotly draws for the same data: after the write, Plotly is asked to
draw the same figure (Panel.sync) and every vertex of its lines must be a vertex of the
written ones (Plotly may drop collinear points; it adds none), the two-point guides equal."""
from __future__ import annotations

import re

import pytest

from test_page import wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

PANELS = ("lobe", "ndf", "g1", "albedo")
# The curves a plot shows, as path strings: its SVG traces' lines, or while a slider is
# held, the runs the canvas over it drew (static/js/panels/heldcanvas.js; test_held_canvas.py
# holds the canvas to them)
PATHS_JS = """(name) => { const gd = document.getElementById(`plot-${name}`);
    if (gd.classList.contains('held-canvas'))
      return gd.heldCurves.map((runs) => runs.map((run) => 'M' + run.map(([x, y]) => `${x},${y}`).join('L')));
    return [...gd.querySelectorAll('.scatterlayer g.trace')]
      .map((g) => [...g.querySelectorAll('path.js-line')].map((p) => p.getAttribute('d'))); }"""
# The plot area's size as Plotly drew it (its public SVG): a cartesian plot's clip, a
# half-disc polar plot's diameter and radius
SIZE_JS = """(n) => { const gd = document.getElementById(`plot-${n}`);
    const line = gd.querySelector('.polarlayer .radial-line line');
    if (line) { const r = Number(line.getAttribute('x2')); return [2 * r, r]; }
    const rect = gd.querySelector('clipPath.axesclip[id$="xy"] rect');
    return [Number(rect.getAttribute('width')), Number(rect.getAttribute('height'))]; }"""
NUMBER = re.compile(r"-?\d+(?:\.\d+)?(?:e-?\d+)?")


def vertices(d: str) -> list[tuple[float, float]]:
    xs = [float(v) for v in NUMBER.findall(d)]
    return list(zip(xs[0::2], xs[1::2]))


@pytest.mark.parametrize("position", [430, 520, 700])
def test_written_paths_are_what_plotly_draws(page, page_log, position):
    page.goto("/?theta_i_deg=50")
    wait_quiet(page)
    # Plotly's state is synced later (idle, pointer, resize): held back until compared
    page.evaluate("""() => { for (const n of ['lobe', 'ndf', 'g1', 'albedo']) {
        const p = window.__brdf.panel(n); p.realSync = p.sync; p.sync = () => Promise.resolve(); } }""")
    move = """(v) => { const s = document.getElementById('alpha-slider');
        s.value = String(v); s.dispatchEvent(new Event('input', { bubbles: true })); }"""
    page.evaluate(move, position)          # a jump: axes re-laid out, a full Plotly draw
    wait_quiet(page)
    page.evaluate(move, position + 4)      # a step: the data moves within the axes
    wait_quiet(page)
    written = {n: page.evaluate(PATHS_JS, n) for n in PANELS}
    written_size = {n: page.evaluate(SIZE_JS, n) for n in PANELS}
    wrote = [n for n in PANELS if page.evaluate("(n) => !!window.__brdf.panel(n).stale", n)]
    assert wrote, "no panel took the path-writing redraw"
    for n in wrote:
        page.evaluate("async (n) => { const p = window.__brdf.panel(n); p.sync = p.realSync; await p.sync(); }", n)
    wait_quiet(page)
    for n in wrote:
        plotly = page.evaluate(PATHS_JS, n)
        size = page.evaluate(SIZE_JS, n)
        # Plotly's redraw may settle its automatic margins a pixel differently than its
        # first draw did (the axes move with the curve): the written points are read
        # on the axes they were written on, in fractions of the plot area
        sx, sy = size[0] / written_size[n][0], size[1] / written_size[n][1]
        assert len(plotly) == len(written[n]), n
        for mine, theirs in zip(written[n], plotly):
            assert len(mine) == len(theirs), n
            for a, b in zip(mine, theirs):
                ours, its = [(x * sx, y * sy) for x, y in vertices(a)], vertices(b)
                assert len(ours) >= len(its) >= 2, (n, len(ours), len(its))
                for x, y in its:      # every vertex Plotly draws in the plot area is one we drew
                    if not (-1 <= x <= size[0] + 1 and -1 <= y <= size[1] + 1):
                        continue      # far off the plot (Λ = 0 on a log axis): clipped, not seen
                    assert min(abs(x - u) + abs(y - v) for u, v in ours) < 0.05, (n, x, y)
    assert page_log.problems() == []


LABELS_JS = """(n) => [...document.querySelectorAll(`#plot-${n} .radial-axis g.xtick text`)].map((t) => t.textContent)"""


def _as_plotly_draws_it(page, name: str, labels_js: str, where, seen_only: bool = False) -> list[str]:
    """The panel's written curve and rewritten labels against Plotly's own draw of the
    same data on the range those labels stand for (Panel.sync, held back by the test
    until now): the same labels, and every vertex Plotly draws one we drew (those in the
    plot's height only, with `seen_only`). Returns the labels."""
    assert page.evaluate("(n) => window.__brdf.panel(n).loose", name)      # refitted on release
    written, labels = page.evaluate(PATHS_JS, name), page.evaluate(labels_js, name)
    page.evaluate("async (n) => { const p = window.__brdf.panel(n); await p.realSync(); }", name)
    wait_quiet(page)
    assert page.evaluate(labels_js, name) == labels, where                # Plotly's own labels there
    assert page.evaluate("(n) => window.__brdf.panel(n).decades", name) is None
    plotly, size = page.evaluate(PATHS_JS, name), page.evaluate(SIZE_JS, name)
    assert len(plotly) == len(written)
    for mine, theirs in zip(written, plotly):
        for a, b in zip(mine, theirs):
            ours, its = vertices(a), vertices(b)
            assert len(ours) >= len(its) >= 2
            for x, y in its:
                if seen_only and not -1 <= y <= size[1] + 1:
                    continue
                assert min(abs(x - u) + abs(y - v) for u, v in ours) < 0.05, (where, x, y)
    return labels


def test_a_held_slider_rescales_the_lobe_axis_by_decades_as_plotly_would(page, page_log):
    """While a slider is held, a lobe whose peak leaves its axis by decades is drawn on
    the axis as it is, scaled by a power of ten, its labels rewritten (static/js/
    decades.js), plain ("200") or as powers ("0.2×10⁴", past 10⁴) and across the two:
    Plotly, drawing the same data on the range those labels stand for, draws the same
    curve and writes the same labels, at each step of a drag over four decades."""
    page.goto("/?theta_i_deg=50")
    wait_quiet(page)
    page.evaluate("""() => { const p = window.__brdf.panel('lobe'); p.realSync = p.sync; p.sync = () => Promise.resolve(); }""")
    move = """(v) => { const s = document.getElementById('alpha-slider');
        s.value = String(v); s.dispatchEvent(new Event('input', { bubbles: true })); }"""
    page.evaluate("() => document.getElementById('alpha-slider').dispatchEvent(new PointerEvent('pointerdown', { bubbles: true }))")
    compared = []
    for position in (500, 420, 340, 260, 200, 150, 110, 150, 230, 330):
        page.evaluate(move, position)
        wait_quiet(page)
        if not page.evaluate("() => window.__brdf.panel('lobe').decades"):
            continue
        compared.append(_as_plotly_draws_it(page, "lobe", LABELS_JS, position))
    assert len(compared) >= 4, compared
    assert any(any("×10" in t for t in c) for c in compared), compared        # powers of ten
    assert any(all("×10" not in t for t in c) for c in compared), compared    # plain decimals
    assert page_log.problems() == []


def test_label_shift_moves_the_decimal_point(page):
    """decades.js shiftLabel against Python's Decimal.scaleb: the same number, written
    as Plotly writes it (no trailing zeros, a Unicode minus); null past the limits."""
    from decimal import Decimal
    page.goto("/")
    cases = [(t, j) for t in ("0", "0.02", "1500", "2.5", "−0.5", "120", "7") for j in range(-4, 5)]
    got = page.evaluate("""async (cases) => { const m = await import('/static/js/panels/decades.js');
        return cases.map(([t, j]) => m.shiftLabel(t, j)); }""", cases)
    for (text, j), out in zip(cases, got):
        value = Decimal(text.replace("−", "-")).scaleb(j)
        plain = format(value.normalize(), "f")
        too_far = abs(value) >= 100_000 or (-value.normalize().as_tuple().exponent > 5)
        if too_far:
            assert out is None, (text, j, out)
        else:
            assert out == plain.replace("-", "−"), (text, j, out)
    assert page.evaluate("""async () => (await import('/static/js/panels/decades.js')).shiftLabel('10\u200b4', 1)""") is None


def test_the_page_spaces_log_ticks_by_the_servers_rule(page):
    """fastdraw.js logDtick, the tick spacing of a log axis the page draws over another
    span than the server's, against the server's own rule (app/figures/style.py)."""
    from app.figures.style import log_dtick
    page.goto("/")
    spans = [0.2, 1.0, 1.5, 1.5001, 2.7, 3.5, 3.5001, 9.99, 10.0, 10.15, 20.3, 31.0]
    got = page.evaluate("""async (spans) => { const m = await import('/static/js/panels/fastdraw.js');
        return spans.map((s) => m.logDtick(s)); }""", spans)
    assert got == [log_dtick(s) for s in spans]


Y_LABELS_JS = """(n) => [...document.querySelectorAll(`#plot-${n} .cartesianlayer g.ytick text`)].map((t) => t.textContent)"""


def test_a_held_slider_moves_the_ndf_log_axis_by_whole_decades_as_plotly_would(page, page_log):
    """While a slider is held, the NDF's peak moving past the top of its log axis is drawn
    on the axis as it is, the curve moved by whole decades and each label's exponent
    with it (static/js/panels/decades.js): Plotly, drawing the same data on the range those
    labels stand for, draws the same curve and writes the same labels, at each step of
    a drag over α both ways."""
    page.goto("/?alpha=0.01")             # an NDF over decades: labelled every whole one
    wait_quiet(page)
    page.evaluate("""() => { const p = window.__brdf.panel('ndf'); p.realSync = p.sync; p.sync = () => Promise.resolve(); }""")
    move = """(v) => { const s = document.getElementById('alpha-slider');
        s.value = String(v); s.dispatchEvent(new Event('input', { bubbles: true })); }"""
    start = int(page.evaluate("() => document.getElementById('alpha-slider').value"))
    page.evaluate("() => document.getElementById('alpha-slider').dispatchEvent(new PointerEvent('pointerdown', { bubbles: true }))")
    compared = []
    for step in range(1, 13):
        page.evaluate(move, start - 25 * step if step <= 8 else start - 25 * (16 - step))
        wait_quiet(page)
        if not page.evaluate("() => window.__brdf.panel('ndf').decades"):
            continue
        # the tail below the axis is cut, not seen
        compared.append(_as_plotly_draws_it(page, "ndf", Y_LABELS_JS, step, seen_only=True))
    assert len(compared) >= 3, compared
    assert len({tuple(c) for c in compared}) >= 2, compared               # the exponents moved
    assert page_log.problems() == []
