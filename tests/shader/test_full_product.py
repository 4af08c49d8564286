"""Every NDF × masking × G2 × Fresnel × diffuse combination /code accepts (one lobe, the
parameterised form a developer ships): at most 300 lines, and the GLSL compiles
(glslangValidator, all programs in one run); the HLSL compiles for a set of programs
that contains every distinct HLSL function and declaration of the whole product (the
HLSL front end needs one run a file; what the product adds beyond those lines is names
side by side, which the GLSL run checks with the same names). The numeric agreement of
each entry: tests/shader/test_code.py; every combination here in WebGL2 against /eval:
tests/e2e/test_webgl_full_product.py. Kulla-Conty with the longest options of every NDF
and of the principled BRDF: the last test."""
from __future__ import annotations

import itertools
import re
import subprocess

import pytest

from app.errors import ParameterError
from app.model import make_spec
from app.physics.diffuse import DIFFUSES
from app.physics.fresnel import FRESNELS
from app.physics.g2 import G2_FORMS
from app.physics.masking import MASKINGS
from app.physics.ndf import NDFS
from app.shader.emit import write
from app.shader.generate import FORMS, program
from tests.shader.test_code import GLSLANG, HLSL_MAIN
from tests.shader.webgl import FRAGMENT_HEAD, FRAGMENT_MAIN

#: a shape away from the special points for the NDFs that take one (the special points:
#: tests/shader/models.py)
SHAPES = {"gtr": {"gamma": 1.5}, "student_t": {"gamma": 3.0}, "exp_power": {"p": 1.5}}
MAX_LINES = 300


def full_product() -> list[dict]:
    out = []
    for ndf, masking, g2, fresnel, diffuse in itertools.product(NDFS, MASKINGS, G2_FORMS, FRESNELS, DIFFUSES):
        params = {"ndf": ndf, "masking": masking, "g2": g2, "fresnel": fresnel, "diffuse": diffuse,
                  "alpha": 0.35, "kd": 0.3, **SHAPES.get(ndf, {})}
        try:
            make_spec(**params)
        except ParameterError:
            continue
        out.append(params)
    return out


@pytest.fixture(scope="module")
def codes():
    """(params, GLSL, HLSL) of every combination: one Program each, written twice."""
    out = []
    for params in full_product():
        prog = program(make_spec(**params), "uniform")
        out.append((params, write(prog, "glsl"), write(prog, "hlsl")))
    return out


def test_the_product_is_the_whole_registry(codes):
    """Every entry of each registry occurs, and the product is not a handful."""
    seen = {key: {p[key] for p, _, _ in codes} for key in ("ndf", "masking", "g2", "fresnel", "diffuse")}
    assert seen == {"ndf": set(NDFS), "masking": set(MASKINGS), "g2": set(G2_FORMS),
                    "fresnel": set(FRESNELS), "diffuse": set(DIFFUSES)}
    assert len(codes) >= len(FRESNELS) * len(DIFFUSES) * 50


def test_no_combination_exceeds_300_lines(codes):
    long = [(len(c.splitlines()), lang, p) for p, glsl, hlsl in codes for lang, c in (("glsl", glsl), ("hlsl", hlsl))
            if len(c.splitlines()) > MAX_LINES]
    assert not long, long[:3]


@pytest.mark.skipif(GLSLANG is None, reason="glslangValidator (Debian glslang-tools) not installed")
def test_every_combination_compiles(codes, tmp_path):
    paths = []
    for k, (_, glsl, _) in enumerate(codes):
        path = tmp_path / f"p{k}.frag"
        path.write_text(FRAGMENT_HEAD + glsl + FRAGMENT_MAIN)
        paths.append(str(path))
    res = subprocess.run([GLSLANG, *paths], capture_output=True, text=True, timeout=600)
    assert res.returncode == 0, res.stdout[-3000:]
    for k in _covering(codes):
        path = tmp_path / f"p{k}.hlsl"
        path.write_text(codes[k][2] + HLSL_MAIN)
        res = subprocess.run([GLSLANG, "-D", "-V", "-e", "main", "-S", "frag", "-o", str(tmp_path / "p.spv"),
                              str(path)], capture_output=True, text=True, timeout=120)
        assert res.returncode == 0, (codes[k][0], res.stdout[-1500:])


def _units(hlsl: str) -> set[str]:
    """The program's functions (whole text) and declarations (one a line; a table by its
    first line), comments and values aside."""
    text = re.sub(r"//[^\n]*", "", hlsl)
    out = set()
    for block in (b.strip() for b in re.split(r"\n\s*\n", text)):
        lines = [line.strip() for line in block.splitlines() if line.strip()]
        if not lines:
            continue
        if lines[0].endswith("{") and "(" not in lines[0]:          # a table: its declaration
            out.add(lines[0])
        elif all(line.endswith(";") for line in lines):            # constants and uniforms
            out |= {re.sub(r"=\s*[-0-9.e+]+;", "= _;", line) for line in lines}
        else:
            out.add(block)
    return out


def _covering(codes) -> list[int]:
    """Greedy: programs until every distinct function and declaration is in one of them."""
    units = [_units(hlsl) for _, _, hlsl in codes]
    missing = set().union(*units)
    chosen = []
    while missing:
        k = max(range(len(units)), key=lambda i: len(units[i] & missing))
        chosen.append(k)
        missing -= units[k]
    return chosen


#: Kulla-Conty with the longest options: two lobes, direction-correlated G2 with van
#: Ginneken's λ(φ), a conductor, EON (measured the longest of Student-t's and GGX's over
#: every masking, G2, λ(φ), Fresnel — a coloured material too — and diffuse model)
KULLA_CONTY_LONGEST = {"alpha": 0.3, "alpha2": 0.7, "lobe_mix": 0.5, "multiscatter": "kulla_conty",
                       "g2": "direction_correlated", "lambda_phi": "van_ginneken", "fresnel": "conductor",
                       "diffuse": "eon", "kd": 0.3}
#: the principled BRDF's longest: every lobe, Kulla-Conty, EON, sRGB decoding
PRINCIPLED_LONGEST = {"model": "principled", "principled_multiscatter": "kulla_conty", "lobe": "all",
                      "principled_diffuse": "eon", "principled_g2": "height_correlated", "base_color_space": "srgb"}


def kulla_conty_models(base: dict = KULLA_CONTY_LONGEST) -> list[dict]:
    """Each NDF with Kulla-Conty: under its default masking, or the Smith integral
    (masking=smith_numeric) where the default Λ is not exact (Blinn-Phong)."""
    out = []
    for ndf in NDFS:
        for masking in ({}, {"masking": "smith_numeric"}):
            params = {"ndf": ndf, **SHAPES.get(ndf, {}), **base, **masking}
            try:
                make_spec(**params)
            except ParameterError:
                continue
            out.append(params)
            break
    return out


def test_kulla_conty_models_stay_within_300_lines(tmp_path):
    """Every NDF that takes Kulla-Conty, and the principled BRDF, with their longest options
    (E's pieces and the Smith fit in the data texture, texture.py): ≤ 300 lines, GLSL and
    HLSL, both forms; the GLSL and HLSL compile with the sampler they declare."""
    models = kulla_conty_models()
    assert {m["ndf"] for m in models} == set(NDFS)
    long, paths = [], []
    for k, params in enumerate(models + [PRINCIPLED_LONGEST]):
        for form in FORMS:
            prog = program(make_spec(**params), form)
            assert prog.texture
            for lang in ("glsl", "hlsl"):
                code = write(prog, lang)
                if len(code.splitlines()) > MAX_LINES:
                    long.append((len(code.splitlines()), lang, form, params))
                assert "BRDF_DATA" in code and not re.search(r"\[\d+\]\s*=", code), "no embedded array left"
            if form == "uniform" and GLSLANG is not None:
                path = tmp_path / f"kc{k}.frag"
                path.write_text(FRAGMENT_HEAD + write(prog, "glsl") + FRAGMENT_MAIN)
                paths.append(str(path))
                hlsl = tmp_path / f"kc{k}.hlsl"
                hlsl.write_text(write(prog, "hlsl") + HLSL_MAIN)
                res = subprocess.run([GLSLANG, "-D", "-V", "-e", "main", "-S", "frag", "-o", str(tmp_path / "kc.spv"),
                                      str(hlsl)], capture_output=True, text=True, timeout=120)
                assert res.returncode == 0, (params, res.stdout[-1500:])
    assert not long, long
    if paths:
        res = subprocess.run([GLSLANG, *paths], capture_output=True, text=True, timeout=600)
        assert res.returncode == 0, res.stdout[-3000:]
