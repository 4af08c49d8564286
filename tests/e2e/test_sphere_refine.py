"""The environment sphere refined at rest (issue 34, static/js/panels/refine.js): left alone, the
panel averages independent renders until its stated noise is at most 5 %, the picture
visibly less noisy; the noise it states is the one the server's own averaging
(app/environment/render.py) states for the same seeds; a slider moved during a
refinement stops it, and the new state's refinement starts over.

At n = 32 (the relative noise does not depend on n; a render costs n²): ~12 renders of a
few hundredths of a second each, where the default n = 256 takes a minute or two. The page
has no control of n (a resolution field); the test declares ``n`` an extra parameter
before the page boots (window.__brdf.declareExtra, the hook other modules use), so that
the link's ``n=32`` goes to the panel's every request."""
from __future__ import annotations

import base64
import json
import re
import urllib.request
from urllib.parse import parse_qs, urlencode, urlparse

import numpy as np
import pytest

from app.environment.render import averaged, stated_noise
from app.lut import png

from test_page import move_slider, wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

N = 32
#: run before the page's scripts: ``n`` declared as the page's main.js defines __brdf
DECLARE_N = """Object.defineProperty(window, '__brdf', { configurable: true,
    set(v) { Object.defineProperty(window, '__brdf', { value: v, writable: true }); v.declareExtra(['n']); } });"""
STATUS_JS = "() => window.__brdf.panel('sphere_env').refiner.status"
# done refining the state the page is in
DONE_JS = """() => { const p = window.__brdf.panel('sphere_env'), s = p.refiner.status;
    return s.done && s.key === p.request().key; }"""
# once a refinement has drawn a render and is still running, the slider moved in the same
# task (nothing runs between the look and the move)
MOVE_WHILE_REFINING_JS = """(value) => { const r = window.__brdf.panel('sphere_env').refiner;
    if (!(r.status.renders >= 1 && r.run)) return false;
    const s = document.getElementById('theta_i-slider');
    s.value = String(value); s.dispatchEvent(new Event('input', {bubbles: true}));
    return true; }"""
HEADING_JS = "() => document.querySelector('#h-sphere_env .sub').textContent"
SOURCE_JS = "() => document.getElementById('plot-sphere_env').data[0].source"


def _roughness(source: str) -> float:
    """Mean |difference| of horizontally neighbouring 8-bit values inside the disk, away
    from its rim: the image's pixel noise (and a little of its shading)."""
    pixels = png.read(base64.b64decode(source.split(",", 1)[1]))[0][..., :3].astype(float)
    n = pixels.shape[0]
    c = (np.arange(n) + 0.5) / n * 2 - 1
    y, x = np.meshgrid(c, c, indexing="ij")
    inside = (x * x + y * y < 0.8)[:, :-1] & (x * x + y * y < 0.8)[:, 1:]
    return float(np.abs(np.diff(pixels, axis=1))[inside].mean())


def _data_requests(log, start: int = 0) -> list[dict[str, str]]:
    out = []
    for url in log.requests[start:]:
        u = urlparse(url)
        if u.path == "/api/v1/sphere_env":
            out.append({k: v[-1] for k, v in parse_qs(u.query).items()})
    return out


def _server_noise(base_url: str, params: dict, seeds: list[int]) -> float:
    """The noise render.py states for the renders of ``seeds`` averaged."""
    pairs = []
    for seed in seeds:
        with urllib.request.urlopen(f"{base_url}/api/v1/sphere_env?{urlencode({**params, 'seed': seed})}") as r:
            body = json.loads(r.read())
        radiance = np.array([[[np.nan if v is None else v for v in px] for px in row] for row in body["radiance"]])
        sigma = np.array([[np.nan if v is None else v for v in row] for row in body["std_error"]])
        on = ~np.isnan(sigma)
        pairs.append((radiance[on], sigma[on]))
    return stated_noise(*averaged(pairs))["relative"]


def test_at_rest_the_sphere_refines_to_five_percent_and_a_slider_starts_it_over(page, page_log, base_url):
    page.add_init_script(DECLARE_N)
    page.goto(f"/?show=sphere_env&n={N}")
    wait_quiet(page, ids=("plot-sphere_env",), timeout=120_000)
    # the figure first drawn: one render at the view's default samples, as the server draws it
    with urllib.request.urlopen(base_url + page.evaluate("() => window.__brdf.url('sphere_env')")) as r:
        first = json.loads(r.read())
    first_noise = float(re.search(r"noise ±([\d.]+)%", first["layout"]["title"]["text"]).group(1)) / 100
    assert first["data"][0]["dx"] == pytest.approx(2 / N)      # an n × n image
    assert first_noise > 0.3                       # 16 samples: ~47 %

    page.wait_for_function(DONE_JS, timeout=120_000)
    status = page.evaluate(STATUS_JS)
    assert status["noise"] <= 0.05 and status["renders"] >= 2
    # the panel's heading states that noise and the samples it comes from
    title = page.evaluate(HEADING_JS)
    stated = float(re.search(r"noise ±([\d.]+)%", title).group(1))
    assert stated == pytest.approx(100 * status["noise"], abs=0.05) and stated <= 5.0
    assert f"at {status['samples']} samples/pixel ({status['renders']} × {status['perRender']})" in title
    # ... which is what the server's averaging states for the same renders
    sent = _data_requests(page_log)
    assert [int(q["seed"]) for q in sent] == status["seeds"] == list(range(1, status["renders"] + 1))
    params = {k: v for k, v in sent[-1].items() if k != "seed"}
    assert status["noise"] == pytest.approx(_server_noise(base_url, params, status["seeds"]), rel=1e-9)
    # and the picture is less noisy than the first one (neighbouring pixels differ less)
    assert _roughness(page.evaluate(SOURCE_JS)) < 0.5 * _roughness(first["data"][0]["source"])

    # a slider moved while a refinement runs stops it: its state's renders are asked no more
    before = page.evaluate("() => window.__brdf.state.theta_i_deg")
    move_slider(page, "theta_i-slider", 20)
    moving = page.evaluate("() => window.__brdf.state.theta_i_deg")
    assert moving != before
    mark = len(page_log.requests)
    page.wait_for_function(MOVE_WHILE_REFINING_JS, arg=60, timeout=120_000, polling=5)
    after = page.evaluate("() => window.__brdf.state.theta_i_deg")
    assert after != moving
    page.wait_for_function(DONE_JS, timeout=120_000)
    again = page.evaluate(STATUS_JS)
    # at the moving state: renders until the move, none after it
    during = _data_requests(page_log, mark)
    cut = next(i for i, q in enumerate(during) if float(q["theta_i_deg"]) == after)
    assert cut >= 1 and all(float(q["theta_i_deg"]) == moving for q in during[:cut])
    later = during[cut:]
    assert all(float(q["theta_i_deg"]) == after for q in later)
    # the new state's refinement started over: from one render, seed 1
    assert again["seeds"] == list(range(1, again["renders"] + 1)) and again["noise"] <= 0.05
    assert [int(q["seed"]) for q in later] == again["seeds"]
    assert page_log.problems() == []


def test_a_busy_server_pauses_the_refinement_and_it_goes_on_when_the_server_can(page, base_url):
    """Three 503s with Retry-After in a row (a loaded server) are waited out, not taken as
    the end: the refinement then goes on to 5 %. It stopped at the third before, its
    heading stating forever the noise of an average that would not improve."""
    busy = {"left": 3, "answered": 0}

    def handle(route):
        if "seed=" in route.request.url and busy["left"] > 0:     # a refining render
            busy["left"] -= 1
            busy["answered"] += 1
            route.fulfill(status=503, headers={"Retry-After": "1", "content-type": "application/json"},
                          body=json.dumps({"detail": "busy (test)"}))
        else:
            route.continue_()

    page.route(re.compile(r".*/api/v1/sphere_env\?.*"), handle)
    page.add_init_script(DECLARE_N)
    page.goto(f"/?show=sphere_env&n={N}")
    wait_quiet(page, ids=("plot-sphere_env",), timeout=120_000)
    page.wait_for_function(DONE_JS, timeout=120_000)
    status = page.evaluate(STATUS_JS)
    assert busy["answered"] == 3 and status["noise"] <= 0.05 and status["renders"] >= 2
    assert status["seeds"] == list(range(1, status["renders"] + 1))   # the refused render asked again
