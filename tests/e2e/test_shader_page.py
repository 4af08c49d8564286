"""The shader tools (static/tools.html, static/js/{pages/tools,pages/shader,pages/lut}.js): the model as
code, the material presets with their RGB Fresnel, the roughness conventions and the LUT
workbench, on a page of their own that the explorer links to with its model, in Chromium.

Issue 34: they were a drawer under the explorer's panels that squeezed the plots into a
~100 px strip, with unstyled buttons, a Fresnel chart cut at θ_d ≈ 58°, a label reading
"isney (Burley 2012)", and a scroll that pushed the top bar off the screen.
"""
from __future__ import annotations

import json
import re
import urllib.request

import numpy as np
import pytest
from playwright.sync_api import expect

from test_page import wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

TIMEOUT = 60_000
DESKTOP = {"width": 1400, "height": 900}
#: a browser's own button background (Chromium: ButtonFace), which a styled button is not
UNSTYLED_BUTTON = "rgb(239, 239, 239)"


def _open(page, query: str = ""):
    page.set_viewport_size(DESKTOP)
    page.goto(f"/tools{query}")
    page.wait_for_selector("#tools[data-ready='1']", timeout=TIMEOUT)


def _inside(inner: dict, outer: dict) -> bool:
    return (inner["x"] >= outer["x"] - 0.5 and inner["x"] + inner["width"] <= outer["x"] + outer["width"] + 0.5
            and inner["y"] >= outer["y"] - 0.5 and inner["y"] + inner["height"] <= outer["y"] + outer["height"] + 0.5)


def test_the_explorer_keeps_its_plots_and_links_the_tools_with_its_model(page, page_log):
    page.set_viewport_size(DESKTOP)
    page.goto("/?ndf=beckmann&alpha=0.2&theta_i_deg=30")
    wait_quiet(page)
    # no drawer under the figures: the panels have the window below the top bar
    assert page.locator("#shader-tools").count() == 0
    assert page.locator("#panels").bounding_box()["height"] > 700
    page.click("#tools-link")
    page.wait_for_selector("#tools[data-ready='1']", timeout=TIMEOUT)
    assert "ndf=beckmann" in page.url and "alpha=0.2" in page.url
    expect(page.locator("#tools-model")).to_contain_text("ndf=beckmann")
    page.click("button[data-lang='glsl']")
    code = page.locator("#shader-code")
    expect(code).to_have_value(re.compile(r"vec3 brdf\(vec3 n, vec3 l, vec3 v\)"), timeout=TIMEOUT)
    text = code.input_value()
    assert "ndf=beckmann" in text and "const float ALPHA_X1 = 0.2;" in text
    page.click("button[data-lang='hlsl']")
    expect(code).to_have_value(re.compile(r"float3 brdf\(float3 n, float3 l, float3 v\)"), timeout=TIMEOUT)
    page.click("button[data-lang='python']")
    expect(code).to_have_value(re.compile(r"def brdf\(n, l, v\):"), timeout=TIMEOUT)
    # back to the explorer with the same model
    page.click("#back-to-explorer")
    page.wait_for_function("() => window.__brdf && window.__brdf.state.ndf === 'beckmann'", timeout=TIMEOUT)
    assert page_log.problems() == []


def test_buttons_are_styled_and_the_top_bar_stays_in_view(page, page_log):
    _open(page)
    for b in page.locator("#tools button").all():
        assert b.evaluate("(e) => getComputedStyle(e).backgroundColor") != UNSTYLED_BUTTON, b.text_content()
    page.evaluate("() => window.scrollTo(0, document.documentElement.scrollHeight)")
    page.wait_for_function("() => window.scrollY > 500")
    top = page.locator(".topbar").bounding_box()
    assert top["y"] == 0 and top["height"] > 30
    assert page_log.problems() == []


def test_material_preset_draws_rgb_fresnel_over_every_angle(page, page_log):
    _open(page, "?material=gold")          # the explorer's link carries the material
    page.wait_for_selector("#material-errors", timeout=TIMEOUT)
    assert page.input_value("#shader-material") == "gold"
    traces = page.evaluate("() => document.querySelector('#material-plot').data.map(t => t.name)")
    assert {"exact R", "exact G", "exact B", "schlick B", "f82_tint G", "gulbrandsen R"} <= set(traces)
    # the θ_d axis is drawn to grazing, 90°, inside the chart (it was cut at ~58°)
    plot = page.locator("#material-plot").bounding_box()
    ticks = {t.text_content(): t.bounding_box() for t in page.locator("#material-plot .xtick text").all()}
    assert "90" in ticks and _inside(ticks["90"], plot), ticks.keys()
    sphere = page.evaluate("() => document.querySelector('#material-sphere').data[0].z")
    centre = sphere[len(sphere) // 2][len(sphere) // 2]
    assert centre[0] > centre[1] > centre[2]         # gold: red > green > blue
    expect(page.locator("#material-errors tr")).to_have_count(4)   # header + schlick, f82_tint, gulbrandsen
    assert page_log.problems() == []


def test_conventions_follow_the_roughness_slider_and_their_labels_are_whole(page, page_log):
    _open(page)
    alpha_gltf = page.locator("#conventions-table tr:nth-child(3) td:nth-child(2)")
    expect(alpha_gltf).to_have_text("0.2500")          # r = 0.5: α = r²
    page.fill("#conventions-roughness", "0.3")
    page.dispatch_event("#conventions-roughness", "input")
    expect(alpha_gltf).to_have_text("0.09000", timeout=TIMEOUT)
    pbrt_v4 = page.locator("#conventions-table tr", has_text="pbrt-v4").locator("td:nth-child(2)")
    expect(pbrt_v4).to_have_text("0.5477")              # α = √0.3
    lobes = page.evaluate("() => document.querySelector('#conventions-plot').data.filter(t => t.type === 'scatter').length")
    assert lobes == 10
    # every ecosystem's name is drawn whole, within the chart ("isney (Burley 2012)" was cut)
    plot = page.locator("#conventions-plot").bounding_box()
    labels = page.locator("#conventions-plot .xtick text").all()
    assert any(t.text_content() == "Disney (Burley 2012)" for t in labels)
    for t in labels:
        assert _inside(t.bounding_box(), plot), t.text_content()
    assert page_log.problems() == []


def test_lut_workbench_builds_a_table_and_diagnoses_a_flipped_upload(page, page_log, base_url, tmp_path):
    _open(page, "?ndf=beckmann")
    page.select_option("#lut-kind", "split_sum")
    page.fill("#lut-size", "8")          # 15² nodes: ~0.3 s of quadrature (16: 31², ~5 s)
    page.click("#lut-build")
    expect(page.locator("#lut-errors tr")).to_have_count(4, timeout=TIMEOUT)    # header + 3 stages
    assert page.locator("#lut-plot").is_visible()
    links = page.locator("#lut-downloads a").evaluate_all("(as) => as.map((a) => a.getAttribute('href'))")
    assert any("format=png" in u and "ndf=beckmann" in u for u in links)
    # a table stored upside down (a classic of PNG row order): the check says so
    with urllib.request.urlopen(f"{base_url}/api/v1/lut?kind=split_sum&size=8&ndf=beckmann&per_texel=false") as res:
        values = np.array(json.load(res)["values"])
    upload = tmp_path / "flipped.json"
    upload.write_text(json.dumps({"values": values[::-1].tolist()}))
    page.set_input_files("#lut-upload", str(upload))
    expect(page.locator("#lut-check")).to_contain_text("flipped along axes[0]", timeout=TIMEOUT)
    assert page_log.problems() == []
