"""The live GPU sphere (static/js/gpu/): drawn from /api/v1/code?form=uniform in the
page's WebGL2 (SwiftShader here), the light dragged, a slider that only sets uniforms, a
model change that compiles once, the truth toggle against the server's float64 frame
for every registry model, and the server's sphere where WebGL2 is missing.

The truth's reference is independent of the GPU path: numpy/numba float64 evaluation
on the server (app/api/routes/environments.py) of the same pixel centres and light.
"""
from __future__ import annotations

import math

import pytest

from test_page import move_slider   # tests/e2e is not a package
from tests.shader.models import registry_models
from tests.shader.principled_models import BUSY

pytestmark = pytest.mark.e2e

#: the target: float32 on the GPU against float64, θ_l, θ_v ≤ 88° (truth.js's band)
REL = 1e-4
#: over the whole disk, terminator and rim included, the difference in units of the
#: frame's peak: there float32's rounding of n·l and n·v (~6e-8 per term of sums that
#: cancel) adds ~1e-7 of the peak; the largest seen is Student-t's at γ = 50, whose D in
#: float32 is good to 1.4e-5 at its highlight (tests/e2e/test_webgl_one_source.py)
ABS_OF_PEAK = REL

READY = "() => window.__gpu && window.__gpu.ok"


def _open(page, url="/?show=gpu"):
    page.goto(url)
    page.wait_for_function(READY, timeout=60_000)


#: The principled BRDF on the panel (its own /code writer): the paper's defaults, and every
#: option's value at least once with every lobe in play.
PRINCIPLED = [{"model": "principled"},
              {**BUSY, "principled_diffuse": "eon", "principled_g2": "height_correlated",
               "principled_multiscatter": "kulla_conty", "base_color_space": "srgb"},
              {**BUSY, "principled_diffuse": "lambert", "anisotropic": 0.6, "lobe": "specular"}]


def test_truth_for_every_registry_model(page, page_log):
    """Each model of the registry list (tests/shader/models.py) and the principled BRDF
    drawn on the GPU and read back from the float target, against the server's float64
    frame of the same light."""
    _open(page)
    bad = []
    for m in registry_models() + PRINCIPLED:
        message = page.evaluate("(m) => window.__gpu.load(m)", m)
        if not page.evaluate("() => window.__gpu.ok"):
            bad.append((m, message))
            continue
        t = page.evaluate("() => window.__gpu.truthNow()")
        if t is None or t["nonFinite"] or t["pixels"] < 40_000 or t["max"] > REL or t["absPeak"] > ABS_OF_PEAK:
            bad.append((m, t))
    assert not bad, bad[:5]
    assert not page_log.problems()


def test_truth_toggle_on_the_page(page, page_log, shots):
    """The toggle's statement on the page: the largest and mean difference, and the
    difference image beside the sphere."""
    _open(page, "/?ndf=beckmann&alpha=0.2&fresnel=conductor&theta_i_deg=30&phi_i_deg=40&show=gpu")
    page.click("#gpu-truth-toggle")
    page.wait_for_function("() => window.__gpu.truth", timeout=60_000)
    text = page.text_content("#gpu-truth")
    t = page.evaluate("() => window.__gpu.truth")
    assert "largest relative difference" in text and "mean" in text
    stated = float(text.split("largest relative difference ")[1].split()[0])
    assert stated == pytest.approx(t["max"], rel=0.06)
    assert t["max"] <= REL and page.is_visible("#gpu-diff")
    page.locator("#panel-gpu").screenshot(path=str(shots / "gpu-truth.png"))
    page.click("#gpu-truth-toggle")
    assert not page.is_visible("#gpu-diff")
    assert not page_log.problems()


def test_drag_slider_and_model_change(page, page_log):
    _open(page, "/?ndf=ggx&alpha=0.3&show=gpu")
    page.wait_for_function("() => window.__gpu.draws > 0")
    before = page.evaluate("() => ({c: window.__gpu.compiles, d: window.__gpu.draws})")
    # the light follows the pointer: pressed at (x, y) on the disk, the light faces it
    box = page.locator("#gpu-canvas").bounding_box()
    cx, cy, r = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2, box["width"] / 2
    page.mouse.move(cx, cy)
    page.mouse.down()
    for k in range(1, 11):
        page.mouse.move(cx + 0.05 * k * r, cy - 0.05 * k * r)
    page.mouse.up()
    page.wait_for_function("() => window.__brdf.pending() === 0")
    x, y = 0.5, 0.5
    state = page.evaluate("() => window.__brdf.state")
    assert state["theta_i_deg"] == pytest.approx(math.degrees(math.asin(math.hypot(x, y))), abs=0.6)
    assert state["phi_i_deg"] == pytest.approx(45.0, abs=0.6)
    after = page.evaluate("() => ({c: window.__gpu.compiles, d: window.__gpu.draws, t: window.__gpu.timings})")
    assert after["c"] == before["c"] and after["d"] >= before["d"] + 5
    assert len(after["t"]) >= 5
    # a slider: new uniforms, no compile
    move_slider(page, "alpha-slider", 600)
    page.wait_for_function("(d) => window.__gpu.draws > d", arg=after["d"])
    page.wait_for_function("() => window.__gpu.model && window.__gpu.model.alpha !== 0.3")
    assert page.evaluate("() => window.__gpu.compiles") == before["c"]
    alpha = page.evaluate("() => window.__brdf.state.alpha")
    assert page.evaluate("() => window.__gpu.code.uniforms.ALPHA_X1") == pytest.approx(alpha)
    # another model: one compile
    page.select_option("select#ndf", "beckmann")
    page.wait_for_function("() => window.__gpu.model && window.__gpu.model.ndf === 'beckmann'")
    assert page.evaluate("() => window.__gpu.compiles") == before["c"] + 1
    assert not page_log.problems()


NO_WEBGL2 = """(() => { const get = HTMLCanvasElement.prototype.getContext;
  HTMLCanvasElement.prototype.getContext = function (kind, ...rest) {
    return kind === 'webgl2' ? null : get.call(this, kind, ...rest); }; })();"""


def test_without_webgl2_the_server_sphere_is_shown(page, page_log):
    page.add_init_script(NO_WEBGL2)
    page.goto("/?show=lobe,gpu")
    page.wait_for_function("() => window.__brdf.pending() === 0 && window.__gpu", timeout=60_000)
    assert "no WebGL2" in page.text_content("#gpu-message")
    assert page.is_visible("#gpu-message")
    assert "sphere" in page.evaluate("() => window.__brdf.state.show")
    page.locator("#plot-sphere").scroll_into_view_if_needed()
    page.wait_for_function("() => window.__brdf.panels().find((p) => p.name === 'sphere').drawn", timeout=60_000)
    assert not page_log.problems()


def test_slice_truth(page, page_log, shots):
    """The θ_h–θ_d slice drawn on the GPU (static/js/gpu/slice.js) against the server's
    float64 f at the same float32 directions (/api/v1/reference/slice), for a sample of
    the registry list (every 8th: each NDF, masking and Fresnel family appears) and the
    principled BRDF; held like the sphere, 1e-4 relative where θ_l, θ_v ≤ 88°."""
    _open(page, "/?ndf=ggx&alpha=0.3&show=gpu")
    page.evaluate("() => window.__gpu.setSlice(true)")
    bad = []
    for m in registry_models()[::8] + PRINCIPLED[:1]:
        page.evaluate("(m) => window.__gpu.load(m)", m)
        page.evaluate("() => window.__gpu.truthNow()")
        t = page.evaluate("() => window.__gpu.sliceTruth")
        if t is None or t["nonFinite"] or t["pixels"] < 60_000 or t["max"] > REL or t["absPeak"] > ABS_OF_PEAK:
            bad.append((m, t))
    assert not bad, bad[:5]
    assert "Slice (φ_d = 90°)" in page.text_content("#gpu-slice-truth")
    page.locator("#panel-gpu").screenshot(path=str(shots / "gpu-slice-truth.png"))
    assert not page_log.problems()
