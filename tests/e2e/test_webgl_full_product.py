"""Issue 32's whole registry in WebGL2 (headless Chromium's SwiftShader, float32), each
program against /api/v1/eval (float64 numpy) to 1e-5 relative where f > 1e-6:

* every NDF × masking × G2 × Fresnel × diffuse combination /code accepts
  (tests/shader/test_full_product.py's full_product(), whose GLSL glslangValidator
  compiles there, all of it, and whose HLSL it compiles for a covering set): the same
  parameterised program (form="uniform"), drawn with /code's uniforms for the material;
* the principled BRDF with every option (tests/shader/principled_models.py's
  principled_models(): 24 option combinations, each lobe alone, the corners), both forms.

What the registry's other test (tests/e2e/test_webgl_one_source.py) keeps beside this:
the shapes at their special points, anisotropy, λ(φ), two lobes, Kulla-Conty, materials.

Cost (SwiftShader compiles each program for 20-60 ms of CPU, its first draw included):
16 × 16 = 256 direction pairs a program, all of a chunk's draws read back as one base64
string (tests/shader/webgl.py's run_packed), one page call per chunk; the chunks (by NDF,
GGX in two) let pytest-xdist's workers share the ~1 500 programs. Each chunk draws its own
random directions (seed from the chunk's name): over the chunks, each term shared between
them (a Fresnel, a diffuse model) meets several thousand different pairs, not 256 again.

Directions as in tests/e2e/test_shader_webgl.py: float64 angles to /eval, float32
vectors to the shader, θ ≤ 88° (off the horizon, where a float32 rounding below it is 0).
"""
from __future__ import annotations

import json
import zlib

import numpy as np
import pytest

from app import quantities
from app.model import make_spec
from app.shader.generate import describe
from tests.shader.conftest import client  # noqa: F401  (the fixture: the API in process)
from tests.shader.principled_models import model_id as principled_id
from tests.shader.principled_models import principled_models
from tests.shader.test_full_product import full_product
from tests.shader.webgl import batch_entry, random_pairs, run_packed

SIDE = 16                         # 256 direction pairs a program
REL, FLOOR = 1e-5, 1e-6

pytestmark = pytest.mark.e2e

#: The chunks, each one page call: an NDF's combinations (GGX's 500 in two, by masking).
GGX_FIRST = ("smith", "smith_numeric")
CHUNKS = {"ggx-smith": lambda m: m["ndf"] == "ggx" and m["masking"] in GGX_FIRST,
          "ggx-approximate": lambda m: m["ndf"] == "ggx" and m["masking"] not in GGX_FIRST,
          **{ndf: (lambda m, ndf=ndf: m["ndf"] == ndf)
             for ndf in ("beckmann", "blinn_phong", "gtr", "student_t", "exp_power")}}


def _id(m: dict) -> str:
    return ",".join(f"{k}={v}" for k, v in m.items() if k not in ("alpha", "kd"))


@pytest.fixture(scope="module")
def page(_profile):
    """A blank page of the session's browser (tests/e2e/conftest.py)."""
    pg = _profile.new_page()
    pg.set_content("<html><body></body></html>")
    yield pg
    pg.close()


def _pairs(name: str):
    """256 random pairs, θ ≤ 88°, a seed per chunk: the angles for /eval (lists), the RGBA texels."""
    angles, rgba = random_pairs(SIDE, zlib.crc32(name.encode()))
    return {k: a.tolist() for k, a in angles.items()}, rgba


def _eval(client, params: dict, angles: dict) -> np.ndarray:
    """/api/v1/eval's f as (pairs, 1), or f_rgb as (pairs, 3) for a coloured model (a
    material's Fresnel gives both; the principled BRDF's f alone is its luminance)."""
    res = client.post("/api/v1/eval", json={**params, **angles, "quantities": _wanted(params)})
    assert res.status_code == 200, (params, res.text[:300])
    body = res.json()
    f = body["f_rgb"] if "f_rgb" in body else [[x] for x in body["f"]]
    return np.array([[np.nan if y is None else y for y in x] for x in f], dtype=float)


def _wanted(params: dict) -> list[str]:
    return ["f_rgb"] if params.get("model") == "principled" else ["f"]


def _evaluated(params: dict, angles: dict) -> np.ndarray:
    """The same numbers from the function /api/v1/eval answers with (quantities.evaluate,
    float64), called in process: through the HTTP client each call cost 17-36 ms against
    0.9 ms, a third of the test's time; :func:`_against_eval` checks that the two agree."""
    a = {k: np.asarray(v, dtype=float) for k, v in angles.items()}
    out = quantities.evaluate(make_spec(**params).brdf(), a["theta_i_deg"], a["phi_i_deg"],
                              a["theta_o_deg"], a["phi_o_deg"], tuple(_wanted(params)))
    f = np.asarray(out[_wanted(params)[0]], dtype=float)
    return f if f.ndim == 2 else f[:, None]


def _against_eval(client, page, name: str, models: list[dict], programs: list[dict], ids: list[str]):
    """Draw each program (the one of its model), against /eval of the model (asked once a
    model): [(id, relative error, or the compile or link error)]."""
    angles, (L, V) = _pairs(name)
    results, _ = run_packed(page, programs, SIDE, L, V)
    assert len(results) == len(programs) == len(models) == len(ids)
    refs: dict[str, np.ndarray] = {}
    out = []
    for m, r, ident in zip(models, results, ids):
        if isinstance(r, str):
            out.append((ident, r[:300]))
            continue
        key = json.dumps(m, sort_keys=True)
        if key not in refs:
            refs[key] = _evaluated(m, angles)
            assert np.isfinite(refs[key]).all(), (ident, "θ ≤ 88°: /eval has no divergence here")
            if len(refs) % 50 == 1:    # every 50th model: /eval itself answers the same numbers
                # (to 1e-12: a model's compiled loop may become ready between the two calls)
                np.testing.assert_allclose(_eval(client, m, angles), refs[key], rtol=1e-12, atol=0,
                                           err_msg=f"{ident}: /eval differs")
        ref = refs[key]
        out.append((ident, float(np.max(np.abs(r[0] - ref) / np.maximum(np.abs(ref), FLOOR)))))
    return out


def _failures(checked) -> list:
    return [(ident, err if isinstance(err, str) else f"relative error {err:.2e}")
            for ident, err in checked if isinstance(err, str) or not err <= REL]


def test_the_chunks_are_the_full_product():
    """Each combination in exactly one chunk: none left out of the browser's run."""
    product = full_product()
    counts = [sum(bool(pred(m)) for pred in CHUNKS.values()) for m in product]
    assert counts == [1] * len(product), [m for m, c in zip(product, counts) if c != 1][:3]
    assert len(product) >= 1400


@pytest.mark.parametrize("chunk", list(CHUNKS))
def test_every_combination_in_webgl2_agrees_with_eval(client, page, chunk):
    """The chunk's combinations, each its parameterised program (what glslangValidator
    compiles in tests/shader/test_full_product.py) with /code's uniforms, against /eval."""
    models = [m for m in full_product() if CHUNKS[chunk](m)]
    bodies = [describe(make_spec(**m), "glsl", "uniform") for m in models]
    programs = [batch_entry(b, [b["uniforms"]]) for b in bodies]
    checked = _against_eval(client, page, chunk, models, programs, [_id(m) for m in models])
    bad = _failures(checked)
    worst = max((c for c in checked if not isinstance(c[1], str)), key=lambda c: c[1], default=("-", 0.0))
    print(f"{chunk}: {len(checked)} programs, worst relative error {worst[1]:.2e} ({worst[0]})")
    assert not bad, f"{len(bad)} of {len(checked)} combinations: {bad[:5]}"


def test_every_principled_option_in_webgl2_agrees_with_eval(client, page):
    """Every option of the principled BRDF (principled_models()), each in both forms: the
    snapshot (derived values baked as float64 constants) and the parameterised program
    (C_tint, C_spec0, α, GTR1's k formed in float32 from the uniforms)."""
    models, programs, ids = [], [], []
    for m in principled_models():
        for form in ("const", "uniform"):
            body = describe(make_spec(**m), "glsl", form)
            models.append(m)
            programs.append(batch_entry(body, [body["uniforms"]] if form == "uniform" else [{}]))
            ids.append(f"{form}: {principled_id(m) or 'the defaults'}")
    checked = _against_eval(client, page, "principled", models, programs, ids)
    worst = max((c for c in checked if not isinstance(c[1], str)), key=lambda c: c[1], default=("-", 0.0))
    print(f"principled: {len(checked)} programs, worst relative error {worst[1]:.2e} ({worst[0]})")
    bad = _failures(checked)
    assert not bad, f"{len(bad)} of {len(checked)} programs: {bad[:5]}"
