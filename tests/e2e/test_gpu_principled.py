"""The principled BRDF's generated GLSL in WebGL2 (headless Chromium's SwiftShader, float32),
every option in one page session, each program compiled once:

* every option's value (tests/shader/principled_models.py's covering set; the Python
  form is checked on every combination in tests/shader) against /api/v1/eval's f_rgb
  (float64, the numpy lobes) — relative 1e-5 where f > 1e-6;
* one compiled uniform-form program drawing two materials by its uniforms alone;
* f finite and ≥ 0 on the closed upper hemisphere up to the horizon, at α's floor.

Directions as in the registry's test (tests/e2e/test_webgl_one_source.py): float64 angles
to /eval, float32 vectors to the shader, θ ≤ 88°.
"""
from __future__ import annotations

import numpy as np
import pytest

from app.model import make_spec
from app.physics.vectors import direction_deg
from app.shader.generate import describe
from tests.shader.conftest import client  # noqa: F401  (the fixture: the API in process)
from tests.shader.principled_models import TWO_MATERIALS, covering_models, model_id
from tests.shader.webgl import FRAGMENT_HEAD, FRAGMENT_MAIN, RUN_BATCH_JS, VERTEX, batch_entry

SIDE = 32                         # 1024 direction pairs per program
REL, FLOOR = 1e-5, 1e-6

pytestmark = pytest.mark.e2e


@pytest.fixture(scope="module")
def page(_profile):
    pg = _profile.new_page()
    pg.set_content("<html><body></body></html>")
    yield pg
    pg.close()


def _pairs():
    rng = np.random.default_rng(11)
    n = SIDE * SIDE
    angles = {"theta_i_deg": rng.uniform(0, 88, n), "phi_i_deg": rng.uniform(-180, 180, n),
              "theta_o_deg": rng.uniform(0, 88, n), "phi_o_deg": rng.uniform(-180, 180, n)}
    l = direction_deg(angles["theta_i_deg"], angles["phi_i_deg"])
    v = direction_deg(angles["theta_o_deg"], angles["phi_o_deg"])
    return angles, [np.concatenate([d, np.zeros((n, 1))], axis=1).astype(np.float32).ravel().tolist() for d in (l, v)]


def _grazing():
    """1024 pairs with θ up to exactly 90° (z = 0: one or both directions on the horizon)."""
    thetas = np.radians([0.0, 30.0, 60.0, 85.0, 89.0, 89.99, 89.9999, 90.0])
    phis = np.radians(np.linspace(-180.0, 180.0, 16, endpoint=False) + 0.5)
    ti, to, p = (a.ravel() for a in np.meshgrid(thetas, thetas, phis, indexing="ij"))
    l = np.stack([np.sin(ti), np.zeros_like(ti), np.cos(ti)], axis=-1)
    v = np.stack([np.sin(to) * np.cos(p), np.sin(to) * np.sin(p), np.cos(to)], axis=-1)
    l[ti == thetas[-1], 2] = 0.0
    v[to == thetas[-1], 2] = 0.0
    return [np.concatenate([d, np.zeros((len(d), 1))], axis=1).astype(np.float32).ravel().tolist() for d in (l, v)]


def _fs(glsl: str) -> str:
    return FRAGMENT_HEAD + glsl + FRAGMENT_MAIN


def _rgb(result) -> np.ndarray:
    return np.array([np.nan if x is None else x for x in result], dtype=float).reshape(-1, 4)[:, :3]


def _f_rgb(client, params, angles) -> np.ndarray:
    res = client.post("/api/v1/eval", json={**params, **{k: a.tolist() for k, a in angles.items()},
                                            "quantities": ["f_rgb"]})
    assert res.status_code == 200, res.text[:300]
    return np.array(res.json()["f_rgb"], dtype=float)


def _error(result, ref) -> float:
    assert np.isfinite(ref).all(), "θ ≤ 88°: no divergence expected"
    return float(np.max(np.abs(_rgb(result) - ref) / np.maximum(np.abs(ref), FLOOR)))


def test_principled_in_webgl2(client, page):
    """Every option's program (compiled once each), the two-material uniform program, and
    the float32 finiteness check, in one page: a page session and its programs are what
    SwiftShader's time goes into."""
    angles, (L, V) = _pairs()
    models = covering_models()
    a, b = TWO_MATERIALS
    code_a, code_b = describe(make_spec(**a), "glsl", "uniform"), describe(make_spec(**b), "glsl", "uniform")
    assert code_a["uniforms"].keys() == code_b["uniforms"].keys() and code_a["uniforms"] != code_b["uniforms"]
    programs = [batch_entry(describe(make_spec(**m), "glsl")) for m in models]
    programs.append(batch_entry(code_a, [code_a["uniforms"], code_b["uniforms"]]))
    out = page.evaluate(RUN_BATCH_JS, [VERTEX, programs, SIDE, SIDE, L, V, [0.0, 0.0, 1.0]])
    assert "error" not in out, out.get("error")
    results = out["results"]
    bad = []
    for m, r in zip(models, results):
        if isinstance(r, dict):
            bad.append((model_id(m), r["error"][:300]))
            continue
        err = _error(r[0], _f_rgb(client, m, angles))
        if not err <= REL:
            bad.append((model_id(m), f"relative error {err:.2e}"))
    ra, rb = results[-1]
    assert not bad, bad[:5]
    assert _error(ra, _f_rgb(client, a, angles)) <= REL
    assert _error(rb, _f_rgb(client, b, angles)) <= REL


def test_principled_finite_in_float32_at_the_horizon(page):
    """At α's floor (roughness 0: α = 0.001; clearcoat gloss 1: α = 0.001) and up to the
    horizon, one uniform program per option set, the corner materials as uniform sets."""
    L, V = _grazing()
    corners = [{"ROUGHNESS": 0.0, "CLEARCOAT": 1.0, "CLEARCOAT_GLOSS": 1.0, "SUBSURFACE": 1.0, "SHEEN": 1.0},
               {"ROUGHNESS": 1.0, "CLEARCOAT_GLOSS": 0.0, "METALLIC": 1.0, "ANISOTROPIC": 1.0},
               {"BASE_R": 0.0, "BASE_G": 0.0, "BASE_B": 0.0, "ROUGHNESS": 0.0, "SUBSURFACE": 0.5}]
    programs = []
    for m in covering_models()[:6]:
        body = describe(make_spec(**m), "glsl", "uniform")
        sets = [{**body["uniforms"], **{k: x for k, x in c.items() if k in body["uniforms"]}} for c in corners]
        programs.append(batch_entry(body, sets))
    out = page.evaluate(RUN_BATCH_JS, [VERTEX, programs, SIDE, SIDE, L, V, [0.0, 0.0, 1.0]])
    assert "error" not in out, out.get("error")
    for r in out["results"]:
        assert not isinstance(r, dict), r
        for f in map(_rgb, r):
            assert np.isfinite(f).all() and (f >= 0).all()
