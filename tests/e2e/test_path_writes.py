"""A slider move's data-only redraw (static/js/svgpaths.js writes the traces' SVG paths
itself) draws what Plotly draws for the same data: after the write, Plotly is asked to
draw the same figure (Panel.sync) and every vertex of its lines must be a vertex of the
written ones (Plotly may drop collinear points; it adds none), the two-point guides equal."""
from __future__ import annotations

import re

import pytest

from test_page import wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

PANELS = ("lobe", "ndf", "g1", "albedo")
PATHS_JS = """(name) => [...document.querySelectorAll(`#plot-${name} .scatterlayer g.trace`)]
    .map((g) => [...g.querySelectorAll('path.js-line')].map((p) => p.getAttribute('d')))"""
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
    wrote = [n for n in PANELS if page.evaluate("(n) => !!window.__brdf.panel(n).stale", n)]
    assert wrote, "no panel took the path-writing redraw"
    for n in wrote:
        page.evaluate("async (n) => { const p = window.__brdf.panel(n); p.sync = p.realSync; await p.sync(); }", n)
    wait_quiet(page)
    for n in wrote:
        plotly = page.evaluate(PATHS_JS, n)
        size = page.evaluate("""(n) => { const fl = document.getElementById(`plot-${n}`)._fullLayout;
            const ax = fl.polar ? fl.polar._subplot.xaxis : fl.xaxis, ay = fl.polar ? fl.polar._subplot.yaxis : fl.yaxis;
            return [ax._length, ay._length]; }""", n)
        assert len(plotly) == len(written[n]), n
        for mine, theirs in zip(written[n], plotly):
            assert len(mine) == len(theirs), n
            for a, b in zip(mine, theirs):
                ours, its = vertices(a), vertices(b)
                assert len(ours) >= len(its) >= 2, (n, len(ours), len(its))
                for x, y in its:      # every vertex Plotly draws in the plot area is one we drew
                    if not (-1 <= x <= size[0] + 1 and -1 <= y <= size[1] + 1):
                        continue      # far off the plot (Λ = 0 on a log axis): clipped, not seen
                    assert min(abs(x - u) + abs(y - v) for u, v in ours) < 0.05, (n, x, y)
    assert page_log.problems() == []
