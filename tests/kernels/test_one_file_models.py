"""Adding an NDF, a Fresnel model or a diffuse model is one file.

A throwaway module written here (never part of the app) registers itself on import, and
is then found everywhere: the compiled loops (agreeing with numpy to 1e-12), the albedo
quadrature, a Kulla-Conty table, and in a new process (where it is imported before the
app, as a file in the package would be) ``/api/v1/models``, ``/eval``, ``/albedo`` with
compensation, ``/code`` and, for the Fresnel model, ``/advise`` and ``method=table``.
Each file writes its formulas once (physics/formula.py); the kernels' scalar functions
and the shaders come from them (WebGL2: tests/e2e/test_webgl_one_source.py).

The NDF is Student-t at γ = 3 written from scratch as an isotropic shape — its D, its
Smith Λ (I_x(2, ½) = 1 − √(1 − x)(1 + x/2) in closed form) and the tail mass of its
slopes, nothing else — so the registered student_t at γ = 3 is an independent reference.
"""
from __future__ import annotations

import importlib
import json
import os
import subprocess
import sys
import textwrap
from dataclasses import replace
from pathlib import Path

import numpy as np
import pytest

from app import kernels
from app.integrate import tables
from app.integrate.albedo import albedo
from app.physics.brdf import BRDF
from app.physics.diffuse import DIFFUSES
from app.physics.fresnel import FRESNELS
from app.physics.g2 import G2_FORMS
from app.physics.masking import MASKINGS
from app.physics.ndf import NDFS

from .test_compiled_matches_numpy import _assert_close, _directions

ROOT = Path(__file__).resolve().parents[2]

NDF_FILE = '''
"""Student-t at γ = 3, written out: a throwaway NDF for the one-file test."""
import math

import numpy as np

from app.physics.formula import Formula
from app.physics.ndf.base import NDFS, ShapeInvariantNDF
from app.physics.numeric import where_valid
from app.physics.scalar import scalar

C = 1.0 / (2.0 * math.sqrt(2.0))      # Γ(5/2)/(Γ(2)√(2π)) · 2/3


@NDFS.register
class T3(ShapeInvariantNDF):
    name = "t3_throwaway"
    label = "t3 (test)"
    description = "Student-t at gamma = 3, for a test."
    reference = "Ribardière et al. 2017"
    menu_order = 99

    @property
    def tail_beta(self):
        return 0.25

    def _D(self, mz, q2):
        return mz * mz / (np.pi * (mz * mz + 0.5 * q2) ** 3)

    def _mu_Lambda(self, mu, s):
        def formula(m, ss):
            a = m / ss
            x = 2.0 / (2.0 + a * a)
            t2 = 0.5 * (1.0 - np.sqrt(1.0 - x) * (1.0 + 0.5 * x))
            return ss * (C * (1.0 + 0.5 * a * a) ** -1.5 - a * t2)
        return where_valid(s > 0, [mu, s], formula, 0.0)

    def radial_ccdf(self, r2):
        return (1.0 + 0.5 * r2) ** -2.0

    def radial_ccdf_inv(self, v):
        return 2.0 * np.expm1(-0.5 * np.log(v))

    def radial_cdf_inv(self, u):
        return 2.0 * np.expm1(-0.5 * np.log1p(-u))

    # the one spelling of D and μΛ: the kernels' D_scalar, mu_Lambda_scalar and the
    # shaders' D and μΛ are generated from it
    D_formula = Formula("D_t3", ("mz", "q2"), "mz * mz / (PI * t * t * t)", body=(("t", "mz * mz + 0.5 * q2"),),
                        consts=(("PI", math.pi, "pi"),))
    mu_Lambda_formula = Formula(
        "muLambda_t3", ("mu", "s2"), "sel(s > 0.0, s * (C * pow(1.0 + 0.5 * a * a, -1.5) - a * t2), 0.0)",
        body=(("s", "sqrt(s2)"), ("a", "mu / max(s, 1e-30)"), ("x", "2.0 / (2.0 + a * a)"),
              ("t2", "0.5 * (1.0 - sqrt(1.0 - x) * (1.0 + 0.5 * x))")),
        consts=(("C", C, "Gamma(5/2)/(Gamma(2) sqrt(2 pi)) 2/3"),))

    @staticmethod
    @scalar
    def radial_ccdf_scalar(r2, p):
        return (1.0 + 0.5 * r2) ** -2.0

    @staticmethod
    @scalar
    def radial_cdf_inv_scalar(u, p):
        return 2.0 * math.expm1(-0.5 * math.log1p(-u))

    @staticmethod
    @scalar
    def radial_ccdf_inv_scalar(v, p):
        return 2.0 * math.expm1(-0.5 * math.log(v))
'''

FRESNEL_FILE = '''
"""A constant reflectance F = F_c: a throwaway Fresnel model for the one-file test."""
import numpy as np

from app.physics.formula import Formula
from app.physics.fresnel.base import FRESNELS, Fresnel
from app.physics.params import Param

FC = Param("f_const", "F_c", 0.0, 1.0, 0.5, "The constant reflectance.")


@FRESNELS.register
class Constant(Fresnel):
    name = "constant_throwaway"
    label = "Constant (test)"
    description = "F = F_c at every angle, for a test."
    params = (FC,)
    menu_order = 99

    def F(self, cos_theta_d):
        return np.full(np.shape(cos_theta_d), self.f_const)

    def F_avg(self):
        return self.f_const

    def schlick_basis(self):
        return ((self.f_const, None),)

    F_formula = Formula("F_constant", ("c",), "f_const", p=("f_const",))
'''

DIFFUSE_FILE = '''
"""A Minnaert-like reciprocal diffuse f_d = ρ/π (μ_l μ_v)^(k−1) with k = 1.3 at most:
a throwaway diffuse model for the one-file test."""
import numpy as np

from app.physics.diffuse.base import DIFFUSES, F_D_ARGS, Diffuse
from app.physics.formula import Formula
from app.physics.params import Param

K = Param("minnaert_k", "k", 1.0, 1.3, 1.2, "Minnaert's exponent.")


@DIFFUSES.register
class Minnaert(Diffuse):
    name = "minnaert_throwaway"
    label = "Minnaert (test)"
    description = "f_d = rho/pi (mu_l mu_v)^(k - 1), for a test."
    params = (K,)
    menu_order = 99

    def f(self, rho, mu_l, mu_v, l_dot_v):
        return (np.asarray(rho, dtype=float) / np.pi
                * (np.asarray(mu_l, dtype=float) * np.asarray(mu_v, dtype=float)) ** (self.minnaert_k - 1.0)
                + 0.0 * np.asarray(l_dot_v))

    f_formula = Formula("fd_minnaert", F_D_ARGS, "rho / 3.141592653589793 * pow(max(mu_l * mu_v, 0.0), k - 1.0)",
                        p=("k",))
'''


MODULES = ("ndf_t3_throwaway", "fresnel_constant_throwaway", "diffuse_minnaert_throwaway")


@pytest.fixture
def throwaway(tmp_path, monkeypatch):
    """Write the two files, import them (they register), unregister afterwards."""
    (tmp_path / "ndf_t3_throwaway.py").write_text(textwrap.dedent(NDF_FILE))
    (tmp_path / "fresnel_constant_throwaway.py").write_text(textwrap.dedent(FRESNEL_FILE))
    (tmp_path / "diffuse_minnaert_throwaway.py").write_text(textwrap.dedent(DIFFUSE_FILE))
    monkeypatch.syspath_prepend(str(tmp_path))
    for m in MODULES:
        importlib.import_module(m)
    yield tmp_path
    NDFS.unregister("t3_throwaway")
    FRESNELS.unregister("constant_throwaway")
    DIFFUSES.unregister("minnaert_throwaway")
    for m in MODULES:
        sys.modules.pop(m, None)


def _lobe(ndf, fresnel=None, masking="smith"):
    return BRDF(ndf, MASKINGS[masking], G2_FORMS["height_correlated"],
                fresnel or FRESNELS["none"]())


@pytest.mark.skipif(not kernels.ENABLED, reason="numba absent or BRDF_FAST=0")
def test_new_ndf_and_fresnel_in_the_compiled_loops(throwaway):
    l, v = _directions()
    for brdf in (_lobe(NDFS["t3_throwaway"](0.3)),
                 _lobe(NDFS["ggx"](0.3), FRESNELS["constant_throwaway"](f_const=0.7)),
                 _lobe(NDFS["t3_throwaway"](0.2), masking="smith_numeric")):
        kernel = kernels.compile_now(brdf, "f")
        assert kernel is not None
        _assert_close(kernel.f(brdf, l, v), brdf.evaluate(l, v, ("f",))["f"])


@pytest.mark.skipif(not kernels.ENABLED, reason="numba absent or BRDF_FAST=0")
def test_new_diffuse_model_in_the_compiled_loops(throwaway):
    """The diffuse file's one formula reaches the compiled loops (directions and degrees
    in) and agrees with its numpy f to 1e-12, beside the throwaway NDF (anisotropic)."""
    model = DIFFUSES["minnaert_throwaway"](minnaert_k=1.25)
    l, v = _directions()
    brdf = replace(_lobe(NDFS["t3_throwaway"](0.2, 0.4)), kd=0.6, diffuse=model)
    kernel = kernels.compile_now(brdf, "f")
    assert kernel is not None
    _assert_close(kernel.f(brdf, l, v), brdf.evaluate(l, v, ("f",))["f"])
    theta = np.linspace(0.0, 90.0, 37)
    got = kernels.f_deg(brdf, theta[:, None], 0.0, theta[None, :], 180.0)
    mu = np.sin(np.deg2rad(90.0 - theta))
    sin = np.sin(np.deg2rad(theta))
    l = np.stack([sin, np.zeros_like(sin), mu], axis=-1)
    v = np.stack([sin * np.cos(np.pi), sin * np.sin(np.pi), mu], axis=-1)
    L, V = np.broadcast_arrays(l[:, None, :], v[None, :, :])
    _assert_close(got.ravel(), brdf.evaluate(L, V, ("f",))["f"].ravel())


def test_new_ndf_in_the_albedo_quadrature_and_a_table(throwaway):
    mine, reference = NDFS["t3_throwaway"](0.4), NDFS["student_t"](0.4, gamma=3.0)
    mu = np.array([0.0, 0.05, 0.3, 0.8, 1.0])
    E = albedo(_lobe(mine), mu, tol=1e-7)
    E_ref = albedo(_lobe(reference), mu, tol=1e-7)
    np.testing.assert_allclose(E.E, E_ref.E, atol=1e-6)
    table = tables.build(tables.table_key(_lobe(mine)), 16, 16)
    for alpha in (0.05, 0.4, 0.9):
        ref = albedo(_lobe(NDFS["student_t"](alpha, gamma=3.0)), mu, tol=1e-7).E
        assert np.max(np.abs(table.E(mu, alpha) - ref)) <= table.error + 1e-6


def test_new_models_through_the_api(throwaway):
    """A new process that imports the two files before the app, as the package would."""
    script = textwrap.dedent('''
        import json
        import ndf_t3_throwaway, fresnel_constant_throwaway
        from fastapi.testclient import TestClient
        from app.main import create_app
        from app.model import make_spec
        from app.integrate import tables
        # the tables first, outside a request (as the server's background builder would):
        # how long they take on a loaded machine is not what is tested here
        tables.table_for(make_spec(ndf="t3_throwaway", fresnel="none", alpha=0.5).brdf())
        tables.table_for(make_spec(fresnel="none").brdf())
        c = TestClient(create_app())
        models = c.get("/api/v1/models").json()
        text = json.dumps(models)
        ev = c.get("/api/v1/eval", params={"ndf": "t3_throwaway", "alpha": 0.3, "fresnel": "none",
                   "theta_i_deg": 30, "phi_i_deg": 0, "theta_o_deg": 30, "phi_o_deg": 180})
        kc = c.get("/api/v1/albedo", params={"ndf": "t3_throwaway", "alpha": 0.5, "fresnel": "none",
                   "multiscatter": "kulla_conty", "n": 5})
        tab = c.get("/api/v1/albedo", params={"fresnel": "constant_throwaway", "f_const": 0.7,
                    "method": "table", "n": 5})
        adv = c.get("/api/v1/advise", params={"fresnel": "constant_throwaway", "tol": 0.05,
                    "alpha_min": 0.2, "alpha_max": 0.4, "theta_max_deg": 60})
        code = [c.get("/api/v1/code", params={"ndf": "t3_throwaway", "alpha": 0.3, "lang": "glsl"}).status_code,
                c.get("/api/v1/code", params={"fresnel": "constant_throwaway", "f_const": 0.7,
                                              "lang": "hlsl"}).status_code]
        print(json.dumps({"listed": ["t3_throwaway" in text, "constant_throwaway" in text],
                          "code": code,
                          "eval": [ev.status_code, ev.json()],
                          "kc": [kc.status_code, kc.json().get("compensation_error"), kc.json().get("E"),
                                 kc.json().get("detail")],
                          "table": [tab.status_code, tab.json().get("E")],
                          "advise": adv.status_code}))
    ''')
    # no time budget: this is about where the models are found, not how fast (a new
    # process may still be compiling their loops on a busy machine)
    env = {**os.environ, "PYTHONPATH": os.pathsep.join([str(throwaway), str(ROOT)]),
           "BRDF_MAX_SECONDS": "600"}
    out = subprocess.run([sys.executable, "-c", script], cwd=ROOT, env=env, timeout=600,
                         capture_output=True, text=True)
    assert out.returncode == 0, out.stderr[-3000:]
    r = json.loads(out.stdout.strip().splitlines()[-1])
    assert r["listed"] == [True, True]
    assert r["code"] == [200, 200], r["code"]      # the shader test: tests/e2e/test_webgl_one_source.py
    assert r["eval"][0] == 200, r["eval"]
    assert r["kc"][0] == 200 and r["kc"][1] <= 1e-3, r["kc"]
    assert np.all(np.abs(np.asarray(r["kc"][2]) - 1.0) <= 2e-3)     # F = 1: the white furnace
    assert r["table"][0] == 200, r["table"]
    assert r["advise"] == 200
