"""The page's "For shader writers" section (static/js/shader.js): the model as code,
the material presets with their RGB Fresnel, and the roughness conventions, in Chromium."""
from __future__ import annotations

import re

import pytest
from playwright.sync_api import expect

pytestmark = pytest.mark.e2e

TIMEOUT = 60_000


def _open(page, live_server, query: str = ""):
    page.goto(f"{live_server}/{query}")
    page.wait_for_load_state("networkidle")
    page.click("#shader-tools > summary", timeout=TIMEOUT)
    page.wait_for_selector("#shader-tools[data-ready='1']", timeout=TIMEOUT)


def test_closed_section_leaves_the_figures_their_height(page, page_log, live_server):
    """Closed (the default) it is one line under the figures: the panels keep the window."""
    page.set_viewport_size({"width": 1280, "height": 800})
    page.goto(f"{live_server}/?show=lobe,slice")
    page.wait_for_selector("#shader-tools > summary", timeout=TIMEOUT)
    assert page.locator("#shader-tools").bounding_box()["height"] < 60
    assert page.locator("#panels").bounding_box()["height"] > 500
    assert page_log.problems() == []


def test_copy_as_glsl_carries_the_page_model(page, page_log, live_server):
    _open(page, live_server, "?ndf=beckmann&alpha=0.2&theta_i_deg=30")
    page.click("button[data-lang='glsl']")
    code = page.locator("#shader-code")
    expect(code).to_have_value(re.compile(r"vec3 brdf\(vec3 n, vec3 l, vec3 v\)"), timeout=TIMEOUT)
    text = code.input_value()
    assert "ndf=beckmann" in text and "const float ALPHA_X1 = 0.2;" in text
    page.click("button[data-lang='hlsl']")
    expect(code).to_have_value(re.compile(r"float3 brdf\(float3 n, float3 l, float3 v\)"), timeout=TIMEOUT)
    page.click("button[data-lang='python']")
    expect(code).to_have_value(re.compile(r"def brdf\(n, l, v\):"), timeout=TIMEOUT)
    assert page_log.problems() == []


def test_material_preset_draws_rgb_fresnel_and_goes_into_the_code(page, page_log, live_server):
    _open(page, live_server)
    page.select_option("#shader-material", "gold")
    page.wait_for_selector("#material-errors", timeout=TIMEOUT)
    traces = page.evaluate("() => document.querySelector('#material-plot').data.map(t => t.name)")
    assert {"exact R", "exact G", "exact B", "schlick B", "f82_tint G", "gulbrandsen R"} <= set(traces)
    sphere = page.evaluate("() => document.querySelector('#material-sphere').data[0].z")
    centre = sphere[len(sphere) // 2][len(sphere) // 2]
    assert centre[0] > centre[1] > centre[2]         # gold: red > green > blue
    rows = page.locator("#material-errors tr")
    expect(rows).to_have_count(4)                   # header + schlick, f82_tint, gulbrandsen
    page.click("button[data-lang='glsl']")
    expect(page.locator("#shader-code")).to_have_value(re.compile(r"material=gold"), timeout=TIMEOUT)
    assert "const float ETA_R = 0.0;" in page.locator("#shader-code").input_value()   # gold's red n = 0
    assert page_log.problems() == []


def test_conventions_follow_the_roughness_slider(page, page_log, live_server, tmp_path):
    _open(page, live_server)
    alpha_gltf = page.locator("#conventions-table tr:nth-child(3) td:nth-child(2)")
    expect(alpha_gltf).to_have_text("0.2500")          # r = 0.5: α = r²
    page.fill("#conventions-roughness", "0.3")
    page.dispatch_event("#conventions-roughness", "input")
    expect(alpha_gltf).to_have_text("0.09000", timeout=TIMEOUT)
    pbrt_v4 = page.locator("#conventions-table tr", has_text="pbrt-v4").locator("td:nth-child(2)")
    expect(pbrt_v4).to_have_text("0.5477")              # α = √0.3
    lobes = page.evaluate("() => document.querySelector('#conventions-plot').data.filter(t => t.type === 'scatter').length")
    assert lobes == 10
    page.locator("#shader-tools").screenshot(path=str(tmp_path / "shader-tools.png"))
    assert page_log.problems() == []
