"""The environment-lit sphere in the page: moving the light redraws it from the light's
new direction (a new request with theta_i_deg, a different image), and the white furnace
sphere shows no edge against its background."""
from __future__ import annotations

import base64

import numpy as np
import pytest

from app.lut import png

from test_page import api_requests, wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

SOURCE_JS = "() => document.getElementById('plot-sphere_env').data[0].source"


def test_moving_the_light_redraws_the_sphere(page, page_log):
    page.goto("/?show=sphere_env&theta_i_deg=20&phi_i_deg=0&kd=0.5")
    wait_quiet(page, ids=("plot-sphere_env",), timeout=120_000)
    before = page.evaluate(SOURCE_JS)
    assert before.startswith("data:image/png;base64,")
    page.fill("#theta_i", "70")
    page.wait_for_function(f"(b) => ({SOURCE_JS})() !== b", arg=before, timeout=120_000)
    assert api_requests(page_log, "sphere_env")[-1]["theta_i_deg"] == "70"
    assert page_log.problems() == []


def test_white_furnace_sphere_vanishes_into_the_background(page, page_log):
    page.goto("/?show=sphere_env&fresnel=none&multiscatter=kulla_conty&alpha=0.5"
              "&sphere_env.environment=uniform")
    wait_quiet(page, ids=("plot-sphere_env",), timeout=120_000)
    assert api_requests(page_log, "sphere_env")[-1]["environment"] == "uniform"
    pixels, _ = png.read(base64.b64decode(page.evaluate(SOURCE_JS).split(",", 1)[1]))
    n = pixels.shape[0]
    y, x = np.mgrid[:n, :n]
    r2 = ((x + 0.5) / n * 2 - 1) ** 2 + ((y + 0.5) / n * 2 - 1) ** 2
    on = r2 < 0.9                                # inside the sphere, away from its rim
    background = pixels[r2 >= 1.0].astype(float).mean()
    assert background == 255.0                  # radiance 1, sRGB white
    # the sphere's pixels are the background to within the stated noise (~10 % in
    # radiance, ~12 levels in sRGB near white; above 1 they clip to white)
    assert abs(pixels[on].astype(float).mean() - background) < 8.0
    assert page_log.problems() == []
