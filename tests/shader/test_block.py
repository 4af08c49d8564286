"""The parameterised form's uniform block (app/shader/block.py): the tables the const form
embeds, the same numbers in the same order, read at the same index; none embedded."""
from __future__ import annotations

import re

import numpy as np
import pytest

from app.model import make_spec
from app.shader import block
from app.shader.dsl import Table
from app.shader.generate import describe

#: two lobes whose Smith Λ is a fit of two shapes (GTR's depends on α): two fits, above
#: block.BLOCK_MIN_FLOATS
FITTED = [{"ndf": "gtr", "gamma": 1.2, "alpha": 0.3, "alpha2": 0.7, "lobe_mix": 0.5},
          {"ndf": "gtr", "gamma": 2.5, "alpha": 0.2, "alpha2": 0.6, "lobe_mix": 0.3}]
#: one fit: cheaper embedded (block.py's measurement)
ONE_FIT = {"ndf": "exp_power", "p": 0.6, "alpha": 0.4}


def _embedded(code: str) -> dict[str, list[float]]:
    """The const form's arrays, read from its text."""
    return {name: [float(x) for x in body.replace("\n", " ").split(",")]
            for name, body in re.findall(r"const float (\w+)\[\d+\] = float\[\d+\]\((.*?)\);", code, re.S)}


@pytest.mark.parametrize("lang", ["glsl", "hlsl"])
@pytest.mark.parametrize("params", FITTED, ids=lambda p: "-".join(f"{k}={v}" for k, v in p.items()))
def test_the_block_holds_what_the_const_form_embeds(params, lang):
    spec = make_spec(**params)
    uniform, const = describe(spec, lang, "uniform"), describe(spec, "glsl", "const")
    arrays = _embedded(const["code"])
    assert arrays, "the const form embeds its fit"
    assert not re.search(r"\bLAM_C\[\d+\]\s*=", uniform["code"]), "no embedded array in the uniform form"
    assert f"{block.NAME}" in uniform["code"] and uniform["textures"] == {}
    b = uniform["blocks"][block.NAME]
    assert b["packing"] == "std140" and len(b["data"]) % 4 == 0
    for name, values in arrays.items():
        part = b["parts"][name]
        assert part["length"] == len(values)
        got = np.array(b["data"][part["offset"]:part["offset"] + part["length"]])
        # the shader's text rounds to float32 (9 significant digits); the block carries float64
        np.testing.assert_allclose(got, values, rtol=1e-8, atol=1e-30)
    assert uniform["lines"] < const["lines"]


def test_one_fit_stays_embedded():
    body = describe(make_spec(**ONE_FIT), "glsl", "uniform")
    assert body["blocks"] == {} and _embedded(body["code"])


def test_kulla_conty_keeps_its_data_texture():
    kc = describe(make_spec(ndf="gtr", gamma=1.2, alpha=0.3, multiscatter="kulla_conty"), "glsl", "uniform")
    assert kc["blocks"] == {} and "BRDF_DATA" in kc["textures"]


@pytest.mark.parametrize("sizes, kind, goes_in", [
    ((), "float", False),                    # nothing to hold
    ((399,), "float", False),                # one fit's worth: cheaper embedded
    ((200, 200), "float", True),             # two tables of 200: 400 numbers
    ((4096,), "float", True),                # 16 KB: WebGL2's smallest MAX_UNIFORM_BLOCK_SIZE
    ((4096, 1), "float", False),             # one number over: stays embedded
    ((500,), "int", False)])                 # the block holds floats
def test_which_tables_go_in_the_block(sizes, kind, goes_in):
    tables = [Table(f"T{k}", [0.5] * n, "", kind) for k, n in enumerate(sizes)]
    assert block.fits(tables) is goes_in


def test_the_python_form_embeds_its_tables():
    py = describe(make_spec(**FITTED[0]), "python", "uniform")
    assert py["blocks"] == {} and "LAM_C = np.array([" in py["code"]
