"""GET /api/v1/code for the principled BRDF: the generated Python agrees with /eval (the
numpy lobes of app/principled, a separate spelling) for every option; the GLSL and HLSL
compile (glslangValidator) and stay ≤ 300 lines; one parameterised program draws another
material by its uniforms alone; f is finite on the closed upper hemisphere. The WebGL2
round trip (float32) is tests/e2e/test_gpu_principled.py."""
from __future__ import annotations

import subprocess
from urllib.parse import urlencode

import numpy as np
import pytest

from tests.shader.principled_models import TWO_MATERIALS, model_id, principled_models
from tests.shader.test_code import GLSLANG, HLSL_MAIN, _angles, _load
from tests.shader.webgl import FRAGMENT_HEAD, FRAGMENT_MAIN

MODELS = principled_models()
#: float64 against float64: the same formulas in another spelling and order
REL, FLOOR = 1e-11, 1e-6
MAX_LINES = 300


def _code(client, params: dict, lang: str, **extra) -> str:
    res = client.get(f"/api/v1/code?{urlencode({**params, 'lang': lang, **extra})}")
    assert res.status_code == 200, res.text
    return res.text


def _f_rgb(client, params: dict, angles: dict) -> np.ndarray:
    res = client.post("/api/v1/eval", json={**params, **angles, "quantities": ["f_rgb"]})
    assert res.status_code == 200, res.text
    return np.array([[np.nan if y is None else y for y in x] for x in res.json()["f_rgb"]], dtype=float)


def _directions(angles: dict):
    from app.physics.vectors import direction_deg
    return (direction_deg(np.array(angles["theta_i_deg"]), np.array(angles["phi_i_deg"])),
            direction_deg(np.array(angles["theta_o_deg"]), np.array(angles["phi_o_deg"])))


def _close(got, ref, what):
    ok = np.isfinite(ref).all(axis=-1)
    assert ok.sum() > 0.9 * len(ref), what
    err = np.abs(got[ok] - ref[ok]) / np.maximum(np.abs(ref[ok]), FLOOR)
    assert err.max() <= REL, f"{what}: relative error {err.max():.2e}"


@pytest.mark.parametrize("params", MODELS, ids=model_id)
def test_python_agrees_with_eval(client, params):
    angles = _angles()
    ns = _load(_code(client, params, "python"))
    l, v = _directions(angles)
    _close(ns["brdf"](np.array([0.0, 0.0, 1.0]), l, v), _f_rgb(client, params, angles), model_id(params))


@pytest.mark.skipif(GLSLANG is None, reason="glslangValidator (Debian glslang-tools) not installed")
def test_glsl_and_hlsl_compile_and_stay_short(client, tmp_path):
    """Every configuration in both forms; one glslangValidator run per language and form
    (it takes many files), so that the check costs seconds, not minutes."""
    for lang, ext, args, wrap in (("glsl", "frag", (), lambda c: FRAGMENT_HEAD + c + FRAGMENT_MAIN),
                                  ("hlsl", "hlsl", ("-D", "-V", "-e", "main", "-S", "frag"), lambda c: c + HLSL_MAIN)):
        for form in ("const", "uniform"):
            paths = []
            for k, params in enumerate(MODELS):
                code = _code(client, params, lang, form=form)
                assert len(code.splitlines()) <= MAX_LINES, (model_id(params), len(code.splitlines()))
                path = tmp_path / f"p{k}_{form}.{ext}"
                path.write_text(wrap(code))
                paths.append(str(path))
            out = ["-o", str(tmp_path / "out.spv")] if lang == "hlsl" else []
            for path in paths:      # HLSL takes one file per run with -o
                res = subprocess.run([GLSLANG, *args, *out, path], capture_output=True, text=True, timeout=120)
                assert res.returncode == 0, (path, res.stdout[-1500:])


def test_one_program_two_materials_by_uniforms(client):
    """The uniform form of material A, its uniforms set to material B's (/code's JSON):
    /eval of B — every derived value (C_tint, C_spec0, α, GTR1's k) formed in the code."""
    a, b = TWO_MATERIALS
    body_a = client.get(f"/api/v1/code?{urlencode({**a, 'lang': 'python', 'form': 'uniform', 'format': 'json'})}").json()
    body_b = client.get(f"/api/v1/code?{urlencode({**b, 'lang': 'python', 'form': 'uniform', 'format': 'json'})}").json()
    assert body_a["uniforms"].keys() == body_b["uniforms"].keys() and body_a["uniforms"] != body_b["uniforms"]
    assert {"BASE_R", "ROUGHNESS", "METALLIC", "CLEARCOAT_GLOSS", "ANISOTROPIC"} <= body_a["uniforms"].keys()
    assert body_a["baked"] == {}
    ns = _load(body_a["code"])
    ns.update(body_b["uniforms"])
    angles = _angles()
    l, v = _directions(angles)
    _close(ns["brdf"](np.array([0.0, 0.0, 1.0]), l, v), _f_rgb(client, b, angles), "material B by uniforms")


def test_kulla_conty_bakes_the_roughness_and_says_why(client):
    params = {"model": "principled", "principled_multiscatter": "kulla_conty", "format": "json",
              "form": "uniform", "lang": "glsl"}
    body = client.get(f"/api/v1/code?{urlencode(params)}").json()
    assert set(body["baked"]) == {"ROUGHNESS", "ANISOTROPIC"} and "roughness" in body["baked"]["ROUGHNESS"]
    assert "METALLIC" in body["uniforms"] and "ROUGHNESS" not in body["uniforms"]
    assert any(a["what"] == "E_1" and a["max_error"] > 0 for a in body["approximations"])


def test_finite_on_the_closed_hemisphere(client):
    """At the horizon (θ = 90° exactly, one or both directions) and at α's floor (roughness
    0: α = 0.001; the clearcoat at gloss 1: α = 0.001): finite, ≥ 0, in the float64 form;
    float32 in WebGL2 is tests/e2e/test_gpu_principled.py."""
    t = np.radians([0.0, 45.0, 89.0, 89.9999, 90.0])
    p = np.radians(np.linspace(-180.0, 180.0, 12, endpoint=False) + 0.5)
    ti, to, pp = (a.ravel() for a in np.meshgrid(t, t, p, indexing="ij"))
    l = np.stack([np.sin(ti), np.zeros_like(ti), np.cos(ti)], axis=-1)
    v = np.stack([np.sin(to) * np.cos(pp), np.sin(to) * np.sin(pp), np.cos(to)], axis=-1)
    l[ti == t[-1], 2] = 0.0
    v[to == t[-1], 2] = 0.0
    for params in MODELS + [{**m, "roughness": 0.0, "clearcoat_gloss": 1.0} for m in MODELS[:24]]:
        f = _load(_code(client, params, "python"))["brdf"](np.array([0.0, 0.0, 1.0]), l, v)
        assert np.isfinite(f).all() and (f >= 0).all(), model_id(params)


def test_models_says_principled_has_a_shader(client):
    families = {f["name"]: f for f in client.get("/api/v1/models").json()["models"]}
    assert families["principled"]["shader"] is True
