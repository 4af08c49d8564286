"""The light dragged on the lit spheres (issue 17): a press on the disk and a drag move
the light so that the surface under the pointer faces it (n = l). Checked against what
the server draws from the new (θ_i, φ_i) alone: the "n = l" marker of the sphere view
lands under the pointer, and the environment sphere's highlight under a point light
lands at the half vector of that light and the viewer."""
from __future__ import annotations

import base64
import math

import numpy as np
import pytest

from app.lut import png

from test_page import api_requests, wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

# data → screen through what Plotly drew: its plot area (the xy subplot's clip rectangle)
# and the axes' ranges it wrote back into the figure's layout
SCREEN_JS = """([id, x, y]) => { const d = document.getElementById(id);
  const r = d.querySelector('clipPath.axesclip[id$="xy"] rect'), n = (a) => Number(r.getAttribute(a));
  const b = d.querySelector('svg.main-svg').getBoundingClientRect();
  const [x0, x1] = d.layout.xaxis.range, [y0, y1] = d.layout.yaxis.range;
  return [b.left + n('x') + (x - x0) / (x1 - x0) * n('width'), b.top + n('y') + (y1 - y) / (y1 - y0) * n('height')]; }"""


def drag(page, plot_id: str, start, end, steps: int = 8) -> None:
    """A real pointer drag between two points given in the plot's data coordinates."""
    x0, y0 = page.evaluate(SCREEN_JS, [plot_id, *start])
    x1, y1 = page.evaluate(SCREEN_JS, [plot_id, *end])
    page.mouse.move(x0, y0)
    page.mouse.down()
    page.mouse.move(x1, y1, steps=steps)
    page.mouse.up()


def test_dragging_on_the_sphere_puts_the_light_under_the_pointer(page, page_log):
    page.goto("/?show=sphere&theta_i_deg=10&phi_i_deg=0")
    wait_quiet(page, ids=("plot-sphere",), timeout=120_000)
    target = (-0.4, 0.6)
    drag(page, "plot-sphere", (0.3, 0.1), target)
    wait_quiet(page, ids=("plot-sphere",), timeout=120_000)
    state = page.evaluate("() => [window.__brdf.state.theta_i_deg, window.__brdf.state.phi_i_deg]")
    # the pointer lands within a pixel of the target: about 0.01 of the radius here
    assert state[0] == pytest.approx(math.degrees(math.asin(math.hypot(*target))), abs=1.0)
    assert state[1] == pytest.approx(math.degrees(math.atan2(target[1], target[0])), abs=1.5)
    # the sidebar follows, and the last request carries the new light
    assert float(page.input_value("#theta_i")) == pytest.approx(state[0], abs=0.05)
    last = api_requests(page_log, "sphere")[-1]
    assert (float(last["theta_i_deg"]), float(last["phi_i_deg"])) == pytest.approx(tuple(state), abs=0.05)
    # the server's own marker of the surface facing the light is under the pointer
    marker = page.evaluate("""() => document.getElementById('plot-sphere').data
        .filter((t) => (t.name || '').startsWith('n = l')).map((t) => [t.x[0], t.y[0]])[0]""")
    assert marker == pytest.approx(list(target), abs=0.03)
    # a held drag asked for coarser images, and the release for the full resolution
    sizes = [r.get("n") for r in api_requests(page_log, "sphere")]
    assert any(n is not None for n in sizes) and sizes[-1] is None, sizes
    assert page_log.problems() == []


def test_the_environment_sphere_highlight_follows_the_dragged_light(page, page_log):
    page.goto("/?show=sphere_env&sphere_env.environment=point&alpha=0.08&kd=0&theta_i_deg=10")
    wait_quiet(page, ids=("plot-sphere_env",), timeout=120_000)
    target = (0.5, -0.35)
    drag(page, "plot-sphere_env", (0.0, 0.2), target)
    wait_quiet(page, ids=("plot-sphere_env",), timeout=120_000)
    theta, phi = page.evaluate("() => [window.__brdf.state.theta_i_deg, window.__brdf.state.phi_i_deg]")
    last = api_requests(page_log, "sphere_env")[-1]
    assert (float(last["theta_i_deg"]), float(last["phi_i_deg"])) == pytest.approx((theta, phi), abs=0.05)
    # the brightest pixel of what is drawn: at the half vector of l and v = (0, 0, 1)
    trace = page.evaluate("() => { const t = document.getElementById('plot-sphere_env').data[0];"
                          " return [t.source, t.x0, t.dx, t.y0, t.dy]; }")
    pixels, _ = png.read(base64.b64decode(trace[0].split(",", 1)[1]))
    lum = pixels[..., :3].astype(float).sum(axis=-1)
    row, col = np.unravel_index(np.argmax(lum), lum.shape)
    at = (trace[1] + col * trace[2], trace[3] + row * trace[4])
    t, p = math.radians(theta), math.radians(phi)
    l = np.array([math.sin(t) * math.cos(p), math.sin(t) * math.sin(p), math.cos(t)])
    h = (l + [0.0, 0.0, 1.0]) / np.linalg.norm(l + [0.0, 0.0, 1.0])
    assert at == pytest.approx((h[0], h[1]), abs=0.06)
    # and the light is the one under the pointer (n = l there)
    assert (l[0], l[1]) == pytest.approx(target, abs=0.03)
    assert page_log.problems() == []
