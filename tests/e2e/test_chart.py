"""The curve panels' chart (static/js/chart/) in a real browser: it draws where the
figure's numbers say, on linear, log, second and polar axes, with labels a reader
expects; its legend hides and shows curves, its tooltip reads the trace's template, a
box drag zooms and a double click undoes it. The pixels are read back from the canvas:
what a person sees, not which code path drew it.
"""
from __future__ import annotations

import pytest

from test_page import wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

# A 600 × 400 chart in the page, drawn from `figure`; the points of the canvas where a
# colour is (within a tolerance), in CSS pixels, read from the pixels the chart painted
# (its canvas is painted in a worker: chart.pixels() asks it).
SETUP_JS = """async (figure) => {
  const { Chart } = await import('/static/js/chart/chart.js');
  let div = document.getElementById('chart-test');
  if (!div) {
    div = document.createElement('div');
    div.id = 'chart-test';
    Object.assign(div.style, { position: 'fixed', left: '0', top: '0', width: '600px', height: '400px',
                               background: '#fff', zIndex: 1000 });
    document.body.append(div);
    window.__chart = new Chart(div);
  }
  await window.__chart.draw(figure, { revision: 'test' });
}"""

FIND_JS = """async (rgb) => {
  const chart = CHART, c = chart.canvas;
  const { width, height, data: px } = await chart.pixels(), dpr = width / c.getBoundingClientRect().width, out = [];
  for (let y = 0; y < height; y++) for (let x = 0; x < width; x++) {
    const k = 4 * (y * width + x);
    if (Math.abs(px[k] - rgb[0]) + Math.abs(px[k + 1] - rgb[1]) + Math.abs(px[k + 2] - rgb[2]) < 40 && px[k + 3] > 200)
      out.push([x / dpr, y / dpr]);
  }
  return out;
}""".replace("CHART", "window.__chart")

RED = [230, 0, 0]
BLUE = [0, 0, 230]


def line(x, y, color="#e60000", **kw):
    return {"type": "scatter", "mode": "lines", "x": x, "y": y, "line": {"color": color, "width": 3}, **kw}


def setup(page, figure):
    page.evaluate(SETUP_JS, figure)
    return page


def rows_and_cols(page, rgb):
    pts = page.evaluate(FIND_JS, rgb)
    assert pts, "the colour is not drawn"
    return sorted({round(p[1]) for p in pts}), sorted({round(p[0]) for p in pts})


@pytest.fixture
def blank(page):
    page.goto("/?show=advise")
    page.wait_for_function("() => window.__brdf && window.__brdf.pending() === 0")
    return page


def test_a_line_is_drawn_where_its_values_are_on_the_axes_given(blank):
    """y = 0.5 over x ∈ [0, 1] on y ∈ [0, 1] sits half-way up the plot; on y ∈ [0, 2],
    three quarters of the way down: the same plot area, the pixel row moved as the range says."""
    layout = {"xaxis": {"range": [0, 1]}, "yaxis": {"range": [0, 1]}}
    setup(blank, {"data": [line([0, 1], [0.5, 0.5]), line([0, 1], [0, 0], color="#0000e6"),
                           line([0, 1], [1, 1], color="#0000e6")], "layout": layout})
    red, _ = rows_and_cols(blank, RED)
    blue, _ = rows_and_cols(blank, BLUE)
    top, bottom = min(blue), max(blue)          # the lines at y = 1 and y = 0 bound the area
    mid = (min(red) + max(red)) / 2
    assert abs(mid - (top + bottom) / 2) <= 2, (mid, top, bottom)
    setup(blank, {"data": [line([0, 1], [0.5, 0.5]), line([0, 1], [0, 0], color="#0000e6")],
                  "layout": {"xaxis": {"range": [0, 1]}, "yaxis": {"range": [0, 2]}}})
    red2, _ = rows_and_cols(blank, RED)
    mid2 = (min(red2) + max(red2)) / 2
    assert abs(mid2 - (top + 0.75 * (bottom - top))) <= 2, (mid2, top, bottom)


def test_a_log_axis_places_decades_evenly_and_labels_them_as_powers(blank):
    """On a log y axis over [10⁻², 10²] (range in decades, as the API sends it), 1 is
    half-way and 10 three quarters of the way up; the labels read 10⁻², 10⁻¹, 1, 10, 10²."""
    fig = {"data": [line([0, 1], [1, 1]), line([0, 1], [10, 10], color="#0000e6"),
                    line([0, 1], [0.01, 0.01], color="#00aa00"), line([0, 1], [100, 100], color="#00aa00")],
           "layout": {"xaxis": {"range": [0, 1]}, "yaxis": {"type": "log", "range": [-2, 2], "dtick": 1}}}
    setup(blank, fig)
    red, _ = rows_and_cols(blank, RED)
    blue, _ = rows_and_cols(blank, BLUE)
    one, ten = (min(red) + max(red)) / 2, (min(blue) + max(blue)) / 2
    labels = blank.evaluate("""async () => { const { Scale } = await import('/static/js/chart/scale.js');
        return new Scale({ type: 'log', range: [-2, 2], dtick: 1 }, [300, 0]).ticks(300, 30).map((t) => t.label); }""")
    assert labels == ["10⁻²", "10⁻¹", "1", "10", "10²"], labels
    # one decade is a quarter of the axis: 10 sits a quarter of the height above 1
    span = blank.evaluate("""async () => { const { Scale } = await import('/static/js/chart/scale.js');
        const s = new Scale({ type: 'log', range: [-2, 2] }, [300, 0]); return [s.px(1), s.px(10), s.px(100)]; }""")
    assert span == [150, 75, 0]
    assert one - ten > 10, (one, ten)
    green, _ = rows_and_cols(blank, [0, 170, 0])        # the lines at 10⁻² and 10² bound the area
    top, bottom = min(green), max(green)
    assert abs(one - (top + bottom) / 2) <= 2, (one, top, bottom)
    assert abs(ten - (top + 0.25 * (bottom - top))) <= 2, (ten, top, bottom)


def test_linear_ticks_are_round_and_angles_keep_their_step(blank):
    out = blank.evaluate("""async () => { const { Scale, tickLabel } = await import('/static/js/chart/scale.js');
        return { deg: new Scale({ range: [0, 90], dtick: 15 }, [0, 600]).ticks(600, 80).map((t) => t.label),
                 auto: new Scale({ range: [0.0222, 0.2078] }, [300, 0]).ticks(300, 44).map((t) => t.label),
                 small: tickLabel(2e-5, 1e-5), neg: tickLabel(-0.25, 0.05) }; }""")
    assert out["deg"] == ["0", "15", "30", "45", "60", "75", "90"], out
    assert out["auto"] == ["0.05", "0.10", "0.15", "0.20"] or out["auto"] == ["0.04", "0.06", "0.08", "0.10", "0.12",
                                                                            "0.14", "0.16", "0.18", "0.20"], out
    assert out["small"] == "2×10⁻⁵" and out["neg"] == "−0.25", out


def test_a_second_axis_draws_its_curve_on_its_own_range(blank):
    """A y2 trace at 50 on y2 ∈ [0, 100] and a y trace at 0.5 on y ∈ [0, 1] are drawn
    on the same row."""
    wide = {**line([0, 1], [0.5, 0.5]), "line": {"color": "#e60000", "width": 9}}     # seen around the other
    setup(blank, {"data": [wide, line([0, 1], [50, 50], color="#0000e6", yaxis="y2")],
                  "layout": {"xaxis": {"range": [0, 1]}, "yaxis": {"range": [0, 1]},
                             "yaxis2": {"range": [0, 100], "overlaying": "y", "side": "right"}}})
    red, _ = rows_and_cols(blank, RED)
    blue, _ = rows_and_cols(blank, BLUE)
    assert abs((min(red) + max(red)) / 2 - (min(blue) + max(blue)) / 2) <= 1.5


def test_a_polar_lobe_is_drawn_in_the_upper_half_towards_its_angle(blank):
    """θ = 0 up and clockwise (the lobe's layout): a ray at θ = 45° runs up and to the
    right of the centre, one at −45° up and to the left."""
    polar = {"sector": [0, 180], "angularaxis": {"rotation": 90, "direction": "clockwise", "dtick": 15},
             "radialaxis": {"range": [0, 1]}}
    ray = lambda th, color: {"type": "scatterpolar", "mode": "lines", "r": [0, 1], "theta": [th, th],
                             "line": {"color": color, "width": 3}}
    setup(blank, {"data": [ray(45, "#e60000"), ray(-45, "#0000e6")], "layout": {"polar": polar}})
    red = blank.evaluate(FIND_JS, RED)
    blue = blank.evaluate(FIND_JS, BLUE)
    # the far ends: the red ray's highest point is right of the blue one's, both above the centre
    r_top = min(red, key=lambda p: p[1])
    b_top = min(blue, key=lambda p: p[1])
    r_low = max(red, key=lambda p: p[1])
    assert r_top[0] > r_low[0] + 50 and b_top[0] < r_low[0] - 50, (r_top, b_top, r_low)
    assert abs(r_top[1] - b_top[1]) <= 2
    # equal lengths: 45° both ways
    dx, dy = r_top[0] - r_low[0], r_low[1] - r_top[1]
    assert abs(dx - dy) <= 4, (dx, dy)


def test_the_legend_hides_and_shows_a_curve(blank):
    setup(blank, {"data": [line([0, 1], [0.2, 0.8], name="model"), line([0, 1], [0.8, 0.2], color="#0000e6", name="data")],
                  "layout": {"xaxis": {"range": [0, 1]}, "yaxis": {"range": [0, 1]}}})
    entries = blank.locator("#chart-test .chart-legend-item")
    assert entries.all_text_contents() == ["model", "data"]
    entries.nth(1).click()
    blank.wait_for_function("() => !window.__chart.painting")
    assert blank.evaluate(FIND_JS, BLUE) == []
    assert blank.evaluate(FIND_JS, RED)
    entries = blank.locator("#chart-test .chart-legend-item")
    entries.nth(1).click()
    blank.wait_for_function("() => !window.__chart.painting")
    assert blank.evaluate(FIND_JS, BLUE)


def test_hover_reads_the_point_in_the_traces_template(blank):
    setup(blank, {"data": [line([0, 0.5, 1], [0.25, 0.5, 0.75], mode="lines+markers",
                                hovertemplate="θ<sub>m</sub>=%{x:.2f}°<br>D=%{y:.4g}<extra></extra>")],
                  "layout": {"xaxis": {"range": [0, 1]}, "yaxis": {"range": [0, 1]}}})
    pts = blank.evaluate(FIND_JS, RED)
    cx = sum(p[0] for p in pts) / len(pts)
    mid = min(pts, key=lambda p: abs(p[0] - cx))
    box = blank.locator("#chart-test canvas").bounding_box()
    blank.mouse.move(box["x"] + mid[0], box["y"] + mid[1])
    tip = blank.locator("#chart-test .chart-tip")
    tip.wait_for(state="visible")
    assert tip.inner_text().split("\n") == ["θm=0.50°", "D=0.5"], tip.inner_text()
    assert tip.locator("sub").all_text_contents() == ["m"]


def test_a_box_drag_zooms_and_a_double_click_undoes_it(blank):
    setup(blank, {"data": [line([0, 1], [0.5, 0.5])], "layout": {"xaxis": {"range": [0, 1]}, "yaxis": {"range": [0, 1]}}})
    _, cols = rows_and_cols(blank, RED)
    box = blank.locator("#chart-test canvas").bounding_box()
    left, right = min(cols), max(cols)
    # the left half of the plot, all its height: the line now spans the whole width again
    blank.mouse.move(box["x"] + left + 2, box["y"] + 40)
    blank.mouse.down()
    blank.mouse.move(box["x"] + (left + right) / 2, box["y"] + 300, steps=5)
    blank.mouse.up()
    blank.wait_for_function("() => window.__chart.zoom && !window.__chart.zooming && !window.__chart.painting")
    x_range = blank.evaluate("() => document.getElementById('chart-test').layout.xaxis.range")
    assert 0 <= x_range[0] < 0.02 and 0.45 < x_range[1] < 0.55, x_range
    _, zoomed = rows_and_cols(blank, RED)
    assert abs(min(zoomed) - left) <= 2 and abs(max(zoomed) - right) <= 2
    blank.mouse.dblclick(box["x"] + left + 50, box["y"] + 100)
    assert blank.evaluate("() => window.__chart.zoom") is None
    blank.wait_for_function("() => !window.__chart.painting")
    # the ranges drawn, as the plot's layout states them: the figure's again
    assert blank.evaluate("() => document.getElementById('chart-test').layout.xaxis.range") == [0, 1]


def test_the_page_draws_the_curves_of_its_answer(page, page_log):
    """The NDF panel's chart after an α move: the figure kept on the plot is the API's
    answer for the new α, and the canvas shows a different curve."""
    page.goto("/?show=ndf&alpha=0.5")
    wait_quiet(page, ids=("plot-ndf",))
    find = FIND_JS.replace("window.__chart", "window.__brdf.panel('ndf').chart")
    curve = lambda: {(round(x), round(y)) for x, y in page.evaluate(find, [0, 114, 178])}
    before = curve()
    page.evaluate("""() => { const s = document.getElementById('alpha-slider');
        s.value = String(Number(s.value) - 150); s.dispatchEvent(new Event('input', { bubbles: true })); }""")
    page.wait_for_function("() => window.__brdf.pending() === 0 && window.__brdf.state.alpha < 0.5")
    wait_quiet(page, ids=("plot-ndf",))
    answer = page.request.get(page.evaluate("() => window.__brdf.url('ndf')")).json()
    drawn = page.evaluate("() => document.getElementById('plot-ndf').layout.yaxis.range")
    assert drawn == answer["layout"]["yaxis"]["range"]
    after = curve()
    assert len(after ^ before) > len(before) / 4
    assert page_log.problems() == []


def test_a_hidden_curve_stays_hidden_when_its_name_moves_with_a_slider(blank):
    """A legend entry that carries a number ("E_avg = 0.049") is renamed at every move:
    a curve the reader hid stays hidden, and the entry reads the new number."""
    def fig(value):
        return {"data": [line([0, 1], [0.2, 0.8], name="model"),
                         line([0, 1], [value, value], color="#0000e6", name=f"E<sub>avg</sub> = {value}")],
                "layout": {"xaxis": {"range": [0, 1]}, "yaxis": {"range": [0, 1]}}}
    setup(blank, fig(0.25))
    blank.locator("#chart-test .chart-legend-item").nth(1).click()
    blank.wait_for_function("() => !window.__chart.painting")
    setup(blank, fig(0.5))
    assert blank.evaluate(FIND_JS, BLUE) == []
    assert blank.locator("#chart-test .chart-legend-item").nth(1).inner_text() == "Eavg = 0.5"
