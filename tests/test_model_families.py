"""Issue 31's extension contract for model families: a throwaway family (Lambert plus a
Phong lobe, two parameters, tests/toy_family.py) written into a temporary directory as
ONE package, no file of the application edited, is found by a server and by the CLI
started with BRDF_MODEL_DIRS naming that directory: in /api/v1/models, /eval, every view
it declares (and a 422 naming ``model`` from the others), its albedo methods (and a 422
naming ``method`` from the others), and ``brdf-explorer export``. The page's menu and
sliders: tests/e2e/test_model_family_ui.py."""
from __future__ import annotations

import json
import math
import os
import subprocess
import sys

import pytest
import requests

from tests.live import ROOT, running_server
from tests.toy_family import NAME, write_family


@pytest.fixture(scope="module")
def toy_dir(tmp_path_factory):
    return write_family(tmp_path_factory.mktemp("families"))


@pytest.fixture(scope="module")
def server(toy_dir):
    with running_server(env={"BRDF_MODEL_DIRS": str(toy_dir)}) as (url, _):
        yield url


def _get(server, path, **params):
    return requests.get(f"{server}/api/v1/{path}", params=params, timeout=120)


@pytest.fixture(scope="module")
def entry(server):
    found = {m["name"]: m for m in _get(server, "models").json()["models"]}
    assert NAME in found, sorted(found)
    return found[NAME]


def test_models_lists_the_family_with_its_two_parameters(entry):
    assert [p["name"] for p in entry["params"]] == ["rho_d", "shininess"]
    assert entry["albedo_methods"] == ["quadrature", "mc_uniform", "mc_cosine"]
    assert set(entry["views"]) == {"lobe", "lobe3d", "sphere", "slice", "ndf", "albedo"}


def test_eval_answers_the_family(server):
    body = _get(server, "eval", model=NAME, rho_d=0.3, shininess=80, theta_i_deg=30,
                theta_o_deg=50, phi_o_deg=180).json()
    assert body["f_diffuse"] == [pytest.approx(0.3 / math.pi, rel=1e-12)]      # Lambert: ρ_d/π
    # the same BRDF spelled as the microfacet model (Walter et al. 2007, eq. 33: α of n)
    same = _get(server, "eval", ndf="blinn_phong", alpha=math.sqrt(2 / 82), fresnel="none", kd=0.3,
                theta_i_deg=30, theta_o_deg=50, phi_o_deg=180).json()
    assert body["f"] == [pytest.approx(same["f"][0], rel=1e-9)]


def test_a_parameter_of_another_family_is_refused(server):
    r = _get(server, "eval", model=NAME, alpha=0.2)
    assert r.status_code == 422 and r.json()["detail"][0]["loc"][-1] == "alpha"
    r = _get(server, "eval", model=NAME, shininess=0.5)
    assert r.status_code == 422 and r.json()["detail"][0]["loc"][-1] == "shininess"
    assert "greater than or equal to 1" in r.text


def test_every_view_that_applies_draws_it_and_the_others_refuse(server, entry):
    small = {"n": 9, "n_theta": 6, "n_phi": 7}
    for view in _get(server, "views").json():
        name, fields = view["name"], {f["name"] for f in view["fields"]}
        r = _get(server, f"figures/{name}", model=NAME, rho_d=0.25,
                 **{k: v for k, v in small.items() if k in fields})
        if name in entry["views"]:
            assert r.status_code == 200, (name, r.text[:300])
            assert "Lambert + Phong" in json.dumps(r.json()["layout"]["title"]), name
        else:
            assert r.status_code == 422, (name, r.status_code)
            assert r.json()["detail"][0]["loc"][-1] == "model", name


def test_its_albedo_methods_answer_and_agree(server, entry):
    answers = {m: _get(server, "albedo", model=NAME, rho_d=0.2, shininess=30, mu="0.3,1",
                       method=m, **({"samples": 65536, "seed": 2} if m.startswith("mc_") else {})).json()
               for m in entry["albedo_methods"]}
    quad = answers["quadrature"]
    for method, body in answers.items():
        assert body["method"] == method
        for E, err, q, q_err in zip(body["E"], body["E_error"], quad["E"], quad["E_error"]):
            assert abs(E - q) <= 5 * err + q_err, method        # Monte Carlo within 5σ
    # Lambert reflects ρ_d = 0.2; the Phong lobe with F = 1 (not energy-balanced against
    # it: a toy) adds at most 1, single scattering loses some to masking
    assert 0.2 + 0.9 < quad["E"][1] <= 0.2 + 1.0 + quad["E_error"][1]


def test_methods_it_does_not_take_are_refused(server):
    r = _get(server, "albedo", model=NAME, method="table")
    assert r.status_code == 422 and r.json()["detail"][0]["loc"][-1] == "method"


def test_the_cli_exports_it(toy_dir, tmp_path):
    env = {**os.environ, "PYTHONPATH": str(ROOT), "BRDF_MODEL_DIRS": str(toy_dir)}
    cli = [sys.executable, "-m", "app.cli"]
    helped = subprocess.run(cli + ["export", "lobe", "--help"], env=env, cwd=ROOT, capture_output=True,
                            text=True, timeout=300)
    assert helped.returncode == 0 and "--rho-d" in helped.stdout and "--shininess" in helped.stdout
    out = tmp_path / "toy.json"
    done = subprocess.run(cli + ["export", "lobe", "--model", NAME, "--rho-d", "0.35", "--shininess", "12",
                                 "--n", "19", "-o", str(out)], env=env, cwd=ROOT, capture_output=True,
                          text=True, timeout=300)
    assert done.returncode == 0, done.stderr
    data = json.loads(out.read_text())
    # 19 angles and the nodes refinement adds; f ≥ the Lambert part ρ_d/π everywhere
    assert len(data["f"]) >= 19 and min(data["f"]) >= 0.35 / math.pi * (1 - 1e-9)
