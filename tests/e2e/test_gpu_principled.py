"""The principled BRDF's generated GLSL in WebGL2 (headless Chromium's SwiftShader, float32),
every option in one page session, each program compiled once:

* one compiled uniform-form program drawing two materials by its uniforms alone, each
  against /api/v1/eval's f_rgb (float64, the numpy lobes) — relative 1e-5 where f > 1e-6
  (every option, both forms, against /eval: tests/e2e/test_webgl_full_product.py);
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
from tests.shader.principled_models import TWO_MATERIALS, covering_models
from tests.shader.webgl import FRAGMENT_HEAD, FRAGMENT_MAIN, batch_entry, run_packed

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


def _f_rgb(client, params, angles) -> np.ndarray:
    res = client.post("/api/v1/eval", json={**params, **{k: a.tolist() for k, a in angles.items()},
                                            "quantities": ["f_rgb"]})
    assert res.status_code == 200, res.text[:300]
    return np.array(res.json()["f_rgb"], dtype=float)


def _error(got: np.ndarray, ref) -> float:
    assert np.isfinite(ref).all(), "θ ≤ 88°: no divergence expected"
    return float(np.max(np.abs(got - ref) / np.maximum(np.abs(ref), FLOOR)))


def test_one_uniform_program_draws_two_materials(client, page):
    """One compiled uniform-form program drawing two materials by its uniforms alone, each
    against /eval of its own material (every option, both forms, one material each:
    tests/e2e/test_webgl_full_product.py)."""
    angles, (L, V) = _pairs()
    a, b = TWO_MATERIALS
    code_a, code_b = describe(make_spec(**a), "glsl", "uniform"), describe(make_spec(**b), "glsl", "uniform")
    assert code_a["uniforms"].keys() == code_b["uniforms"].keys() and code_a["uniforms"] != code_b["uniforms"]
    (result,), _ = run_packed(page, [batch_entry(code_a, [code_a["uniforms"], code_b["uniforms"]])], SIDE, L, V)
    assert not isinstance(result, str), result
    ra, rb = result
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
    results, _ = run_packed(page, programs, SIDE, L, V)
    for r in results:
        assert not isinstance(r, str), r
        for f in r:
            assert np.isfinite(f).all() and (f >= 0).all()
