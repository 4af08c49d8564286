"""The generated GLSL in the page's WebGL2 context (headless Chromium): compiled, run on
4096 direction pairs into a float32 colour buffer, read back, and compared with
/api/v1/eval — relative 1e-5 where f > 1e-6 — for a set of models in which every
registry entry (each NDF, masking, G2 form, λ(φ), Fresnel, multiple scattering, two
lobes, anisotropy, each embedded table) occurs at least once; a Kulla-Conty shader with
its data texture (/code's JSON "textures") bound.

Directions are drawn in float64, sent to the shader as float32 (rounding 6e-8) and to
/eval as angles; θ ≤ 88° keeps the comparison off the horizon, where f of a float32
direction a rounding below it is 0."""
from __future__ import annotations

import json
import urllib.request
from urllib.parse import urlencode

import numpy as np
import pytest

from tests.shader.models import model_id
from tests.shader.webgl import FRAGMENT_HEAD, FRAGMENT_MAIN, RUN_JS, VERTEX, random_pairs

pytestmark = pytest.mark.e2e

SIDE = 64                       # 64 × 64 = 4096 direction pairs per model
REL, FLOOR = 1e-5, 1e-6

COVERING = [
    {"ndf": "ggx", "alpha": 0.3},
    {"ndf": "ggx", "alpha": 0.25, "alpha_y": 0.5, "masking": "smith_numeric", "g2": "separable",
     "fresnel": "dielectric"},
    {"ndf": "ggx", "alpha": 0.4, "masking": "karis", "g2": "hammon", "fresnel": "conductor"},
    {"ndf": "ggx", "alpha": 0.4, "masking": "schlick_direct", "g2": "direction_correlated", "fresnel": "none"},
    {"ndf": "ggx", "alpha": 0.3, "masking": "schlick_ibl", "g2": "height_direction_correlated",
     "lambda_phi": "van_ginneken", "kd": 0.3, "alpha2": 0.7, "lobe_mix": 0.4},
    {"ndf": "ggx", "alpha": 0.5, "multiscatter": "kulla_conty", "alpha2": 0.2, "lobe_mix": 0.3},
    {"ndf": "beckmann", "alpha": 0.4, "multiscatter": "kulla_conty", "fresnel": "conductor"},
    {"ndf": "beckmann", "alpha": 0.3, "masking": "walter", "g2": "separable"},
    {"ndf": "blinn_phong", "alpha": 0.35, "masking": "smith_numeric"},
    {"ndf": "blinn_phong", "alpha": 0.35},
    {"ndf": "gtr", "alpha": 0.3, "gamma": 1.5},
    {"ndf": "student_t", "alpha": 0.3, "alpha_y": 0.45, "gamma": 3.0},
    {"ndf": "exp_power", "alpha": 0.3, "p": 0.5},
    {"ndf": "ggx", "alpha": 0.3, "material": "gold"},
    {"ndf": "ggx", "alpha": 0.5, "material": "copper", "multiscatter": "kulla_conty"},
]


def _get(url: str) -> bytes:
    with urllib.request.urlopen(url, timeout=300) as res:
        return res.read()


def _eval(base: str, params: dict, angles: dict) -> np.ndarray:
    body = json.dumps({**params, **angles, "quantities": ["f"]}).encode()
    req = urllib.request.Request(f"{base}/api/v1/eval", data=body, method="POST",
                                 headers={"Content-Type": "application/json"})
    with urllib.request.urlopen(req, timeout=300) as res:
        body = json.loads(res.read())
    if "f_rgb" in body:                        # a material: one f per channel
        return np.array(body["f_rgb"], dtype=float)
    return np.array([np.nan if x is None else x for x in body["f"]], dtype=float)[:, None]


@pytest.fixture(scope="module")
def pairs():
    angles, rgba = random_pairs(SIDE, 11)
    return {k: a.tolist() for k, a in angles.items()}, rgba


@pytest.mark.parametrize("params", COVERING, ids=model_id)
def test_glsl_in_webgl2_agrees_with_eval(page, live_server, pairs, params):
    angles, (l_rgba, v_rgba) = pairs
    body = json.loads(_get(f"{live_server}/api/v1/code?{urlencode({**params, 'lang': 'glsl', 'format': 'json'})}"))
    page.goto(live_server + "/")
    out = page.evaluate(RUN_JS, [VERTEX, FRAGMENT_HEAD + body["code"] + FRAGMENT_MAIN, SIDE, SIDE,
                                 l_rgba, v_rgba, [0.0, 0.0, 1.0], {**body["textures"], **body["blocks"]}])
    assert "error" not in out, out.get("error")
    got = np.array(out["f"], dtype=float).reshape(-1, 4)[:, :3]
    ref = _eval(live_server, params, angles)
    assert np.isfinite(ref).all(), "θ ≤ 88°: no divergence expected"
    err = np.abs(got - ref) / np.maximum(np.abs(ref), FLOOR)
    worst = np.unravel_index(np.argmax(err), err.shape)
    assert err.max() <= REL, f"relative error {err.max():.2e} (f = {ref[worst]:.3g})"
