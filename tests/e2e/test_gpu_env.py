"""The sphere under a procedural environment on the GPU (static/js/gpu/env.js),
progressive: samples accumulate across frames, and the image's mean luminance is held to
the server's multiple-importance-sampled render (views/sphere_env.py, float64, its own
stated standard error) within 4 combined standard errors.

Held: uniform (the white furnace) and the two environments with soft-edged bright discs
(studio's key box, sunset's sun), which the GPU drew 0.5 % and 2 % too bright while their
edge cosines came from SwiftShader's float32 cos() (docs/gpu.md). Overcast, which has no
edge, agreed at 0.3 σ then and is covered by the same code path.

The stated noise (each pixel's standard error from its own samples, RMS over the disk,
over the mean: render.py's ``noise.relative``) is checked against the spread of two
independent images, and is at or below the server's at 16 samples a pixel within the
pairs that the issue's 2 s of rest give at ~20 pairs a second (measured: uniform 32,
studio 8, sunset 16 pairs; uniform took ~180 before the glossy lobe strategy). While the light is dragged the sphere accumulates a coarse preview
(bench/gpu_env.py measures its frame rate) and returns to full size at rest.

One page for the module: each test sets the environment it needs, which restarts the
accumulation."""
from __future__ import annotations

import math

import numpy as np
import pytest

from test_gpu_hdr import encode   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

URL = "/?show=gpu&alpha=0.3&kd=0.3&theta_i_deg=40&phi_i_deg=135"
#: Rec. 709 luminance, on which the noise is stated (render.py)
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])
#: The issue's target: at rest, the server's stated noise reached within 2 s. Held here
#: in sample pairs, which the load does not change: 2 s at the ~20 pairs a second
#: measured at 256² at load ~5 (bench/gpu_env.py measures the seconds themselves).
REST_PAIRS = 40



@pytest.fixture(scope="module")
def page(_profile, live_server):
    pg = _profile.new_page()
    pg.goto(live_server + URL)
    pg.wait_for_function("() => window.__gpu && window.__gpu.ok", timeout=60_000)
    yield pg
    pg.close()


@pytest.mark.parametrize("env", ["uniform", "studio", "sunset"])
def test_environment_sphere_converges_to_the_server(page, page_log, shots, env):
    page.evaluate("(e) => window.__gpu.setEnvironment(e)", env)
    page.wait_for_function("() => { const e = window.__gpu.env; return e && e.reference && e.samples >= 32; }",
                           timeout=120_000, polling=500)
    e = page.evaluate("() => window.__gpu.env")
    ref = e["reference"]
    sigma = math.hypot(e["error"], ref["mean_radiance_error"])
    assert abs(e["mean"] - ref["mean_radiance"]) <= 4 * sigma, (e, ref)
    # the server's noise at 16 samples a pixel, reached here within 2 s of rest
    history = page.evaluate("() => window.__gpu.envHistory")
    reached = next((h for h in history if h["relative"] <= ref["relative"]), None)
    assert reached and reached["samples"] <= REST_PAIRS, (reached, ref["relative"])
    text = page.text_content("#gpu-env-text")
    assert "σ" in text and f"±{100 * ref['relative']:.2g} %" in text
    page.locator("#gpu-env-canvas").screenshot(path=str(shots / f"gpu-env-{env}.png"))
    assert not page_log.problems()


def test_stated_noise_is_the_spread_of_independent_images(page, page_log):
    """Two images from independent random numbers: the RMS of their per-pixel difference
    over the mean is √2 × the noise each states (the estimator is unbiased, so their
    difference is noise alone). Over ~51 000 pixels the two agree to 0.04 % (measured);
    5 % leaves room for the heavy tail of the highlight's pixels."""
    page.evaluate("() => window.__gpu.setEnvironment('studio')")
    page.wait_for_function("() => window.__gpu.env")
    a, b = (page.evaluate("(s) => window.__gpu.envIndependent(s, 32)", seed) for seed in (1, 2))
    diff = (np.reshape(a["means"], (-1, 3)) - np.reshape(b["means"], (-1, 3))) @ LUMINANCE
    mean = 0.5 * (a["stats"]["mean"] + b["stats"]["mean"])
    measured = float(np.sqrt(np.mean(diff ** 2)) / mean / math.sqrt(2))
    stated = math.sqrt(0.5 * (a["stats"]["relative"] ** 2 + b["stats"]["relative"] ** 2))
    assert measured == pytest.approx(stated, rel=0.05), (measured, stated)
    assert not page_log.problems()


def test_drag_previews_coarse_and_rests_at_full_size(page, page_log, shots):
    page.evaluate("() => window.__gpu.setEnvironment('studio')")
    box = page.locator("#gpu-canvas").bounding_box()
    cx, cy, r = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2, box["width"] * 0.3
    page.evaluate("() => window.__gpu.clearTimings()")
    page.mouse.move(cx + r, cy)
    page.mouse.down()
    for k in range(1, 13):
        page.mouse.move(cx + r * math.cos(k * math.pi / 6), cy + r * math.sin(k * math.pi / 6))
    assert page.evaluate("() => window.__gpu.envPreviewing")
    page.locator("#gpu-env-canvas").screenshot(path=str(shots / "gpu-env-preview.png"))
    page.mouse.up()
    frames = page.evaluate("() => window.__gpu.envFrames")
    assert sum(f["preview"] for f in frames) >= 5
    # at rest: full size again, the noise stated and falling
    page.wait_for_function("() => !window.__gpu.envPreviewing && window.__gpu.env && window.__gpu.env.samples >= 8",
                           polling=100, timeout=60_000)
    assert "noise ±" in page.text_content("#gpu-env-text")
    # an exposure only redraws: the samples keep accumulating
    before = page.evaluate("() => window.__gpu.env.samples")
    page.evaluate("""() => { const s = document.getElementById('gpu-exposure');
        s.value = '1'; s.dispatchEvent(new Event('input', {bubbles: true})); }""")
    page.wait_for_function("(n) => window.__gpu.env.samples > n", arg=before, polling=100)
    assert not page.evaluate("() => window.__gpu.envPreviewing")
    assert not page_log.problems()


#: A Lambertian white surface (f = 1/π: the principled BRDF's Lambert diffuse lobe alone)
LAMBERT = {"model": "principled", "lobe": "diffuse", "principled_diffuse": "lambert", "base_color": "#ffffff"}


def test_a_users_hdr_lights_the_sphere_as_the_closed_form(page, page_log, shots):
    """A .hdr whose red is the hemisphere about +y, green about +x, blue about +z (the
    map's layout: row 0 at +y, its centre column seen behind the sphere, −z): a Lambertian
    white surface's radiance in each channel is then (1 + n·a)/2 (the irradiance of a
    hemisphere of unit radiance, π(1 + cos β)/2). Each channel's mean residual on either
    side of the disk's median along its axis is 0 within 4 standard errors (from the
    residuals' own spread); a map read upside down or mirrored would miss by ~0.2."""
    h, w = 32, 64
    theta = np.pi * (np.arange(h) + 0.5) / h
    phi = -np.pi + 2 * np.pi * (np.arange(w) + 0.5) / w
    T, P = np.meshgrid(theta, phi, indexing="ij")
    d = np.stack([np.sin(T) * np.sin(P), np.cos(T), -np.sin(T) * np.cos(P)], axis=-1)   # x, y, z
    img = np.stack([d[..., 1] > 0, d[..., 0] > 0, d[..., 2] > 0], axis=-1).astype(float)
    assert page.evaluate("(m) => window.__gpu.load(m)", LAMBERT)
    assert page.evaluate("(b) => window.__gpu.openHdr(b, 'axes.hdr')", list(encode(img)))
    got = np.reshape(page.evaluate("() => window.__gpu.envIndependent(7, 32)")["means"], (-1, 3))
    n = 256
    c = -1 + (2 * np.arange(n) + 1) / n
    y, x = np.meshgrid(c, c, indexing="ij")                  # rows from the bottom, as read back
    on = x * x + y * y < 1
    normal = np.stack([x[on], y[on], np.sqrt(1 - x[on] ** 2 - y[on] ** 2)], axis=-1)
    for ch, axis in enumerate((1, 0, 2)):
        residual = got[:, ch] - (1 + normal[:, axis]) / 2
        for side in (normal[:, axis] >= np.median(normal[:, axis]), normal[:, axis] < np.median(normal[:, axis])):
            r = residual[side]
            assert abs(r.mean()) <= 4 * r.std() / np.sqrt(len(r)), ("rgb"[ch], r.mean(), r.std())
    page.wait_for_function("() => window.__gpu.env && window.__gpu.env.samples >= 16", polling=200)
    assert "axes.hdr" in page.text_content("#gpu-env-text")
    page.locator("#gpu-env-canvas").screenshot(path=str(shots / "gpu-env-hdr.png"))
    # not a .hdr: the server's reason, and the sphere stands
    assert not page.evaluate("() => window.__gpu.openHdr([80, 78, 71], 'not.hdr')")
    assert "not.hdr" in page.text_content("#gpu-message") and "#?RADIANCE" in page.text_content("#gpu-message")
    page.evaluate("() => window.__gpu.load(null)")
    assert [p for p in page_log.problems() if "environments/hdr" not in p and "status of 422" not in p] == []
