"""GET /api/v1/lut: each kind's reported error bounds its true error, measured against an
independent quadrature (tests/shader/reference_albedo.py) at texel centres and at the
half-texel offsets the lookup error claims; exports and uploads; bad input."""
from __future__ import annotations

import io
import json
import zipfile
from urllib.parse import urlencode

import numpy as np
import pytest

from app.lut import png
from app.lut.build import LobeKey, alpha_of, mu_of
from app.lut.table import KINDS
from app.model import make_spec
from tests.shader import reference_albedo

SIZE = 8
MODELS = [{"ndf": "ggx"},
          {"ndf": "beckmann", "g2": "separable", "mu_axis": "sqrt_mu", "roughness_axis": "alpha"}]


def _get(client, **query):
    res = client.get(f"/api/v1/lut?{urlencode(query)}")
    assert res.status_code == 200, res.text
    return res


def _reference(lobe_key, kind, roughness_axis, mu_axis, xr, xm):
    """Exact channels at the axis positions (xr, xm) and the reference's error."""
    alpha = float(alpha_of(roughness_axis, xr))
    if kind == "kc_E_avg":
        e, err = reference_albedo.albedo_average(lobe_key.lobe(alpha, None))
        return np.array([e]), err
    mu = float(mu_of(mu_axis, xm))
    e1, err1 = reference_albedo.albedo(lobe_key.lobe(alpha, None), mu)
    if kind == "kc_E":
        return np.array([e1]), err1
    es, errs = reference_albedo.albedo(lobe_key.lobe(alpha, 5.0), mu)
    pair = [e1 - es, es] if kind == "split_sum" else [es, e1]
    return np.array(pair), err1 + errs


def _lookup(values, i, j, di, dj):
    """Bilinear lookup of the quantised texels half a texel up either axis (exact weights)."""
    rows = [i, i + 1] if di else [i]
    cols = [j, j + 1] if dj else [j]
    return np.mean([values[r][c] for r in rows for c in cols], axis=0)


@pytest.mark.parametrize("model", MODELS, ids=lambda m: m["ndf"])
@pytest.mark.parametrize("kind", list(KINDS))
def test_reported_error_bounds_true_error(client, kind, model):
    params = {k: v for k, v in model.items() if not k.endswith("_axis")}
    axes = {k: v for k, v in model.items() if k.endswith("_axis")}
    if kind == "kc_E_avg":
        axes.pop("mu_axis", None)
    key = LobeKey.of(make_spec(**params).brdf())
    rng = np.random.default_rng(2)
    texels = [(0, 0), (SIZE - 2, SIZE - 2), (SIZE // 2, 1)] + [tuple(rng.integers(0, SIZE - 1, 2)) for _ in range(2)]
    if kind == "kc_E_avg":
        texels = [(i, 0) for i in (0, 3, SIZE - 2)]
    refs = {}
    for quantisation in ("unorm8", "unorm16", "float16", "float32"):
        body = _get(client, kind=kind, size=SIZE, quantisation=quantisation, **params, **axes).json()
        values = np.array(body["values"])
        err = body["error"]
        r_values = np.array(body["axes"][0]["values"])
        m_values = np.array(body["axes"][1]["values"]) if kind != "kc_E_avg" else None
        for i, j in texels:
            offsets = [(0, 0), (1, 0)] if kind == "kc_E_avg" else [(0, 0), (1, 0), (0, 1), (1, 1)]
            for di, dj in offsets:
                xr = r_values[i] + di * 0.5 / SIZE
                xm = None if m_values is None else m_values[j] + dj * 0.5 / SIZE
                if (i, j, di, dj) not in refs:
                    refs[(i, j, di, dj)] = _reference(key, kind, body["axes"][0]["name"],
                                                      body["axes"][-1]["name"], xr, xm)
                exact, ref_err = refs[(i, j, di, dj)]
                if kind == "kc_E_avg":
                    got = np.mean([values[i + k] for k in range(di + 1)], axis=0)
                    bound = np.array(err["lookup"]["per_texel"][i])
                else:
                    got = _lookup(values, i, j, di, dj)
                    bound = np.array(err["lookup"]["per_texel"][i][j])
                assert np.all(np.abs(got - exact) <= bound + ref_err), (quantisation, i, j, di, dj, got, exact, bound)
                if (di, dj) == (0, 0):
                    q_bound = np.array(err["quantised"]["per_texel"][i][j] if kind != "kc_E_avg"
                                       else err["quantised"]["per_texel"][i])
                    assert np.all(np.abs(got - exact) <= q_bound + ref_err)


def test_8_bit_split_sum_shows_its_banding(client):
    body = _get(client, kind="split_sum", size=32, quantisation="unorm8", per_texel="false").json()
    assert body["error"]["lookup"]["max_overall"] > 1 / 255
    # at the texel centres the quantisation alone: half a step, plus the integral's bound
    assert body["error"]["quantised"]["max_overall"] <= 0.5 / 255 + body["error"]["table"]["max_overall"]
    body16 = _get(client, kind="split_sum", size=32, quantisation="unorm16", per_texel="false").json()
    assert body16["error"]["quantised"]["max_overall"] < 1e-4


def test_png_round_trip_and_flip_detection(client):
    res = _get(client, kind="split_sum", size=SIZE, format="png")
    samples, bits = png.read(res.content)
    assert bits == 16 and samples.shape == (SIZE, SIZE, 3) and not samples[..., 2].any()
    table = np.array(_get(client, kind="split_sum", size=SIZE, quantisation="unorm16").json()["values"])
    assert np.array_equal(samples[..., :2], np.round(table * 65535).astype(int))
    ok = client.post("/api/v1/lut/check?kind=split_sum", content=res.content,
                     headers={"content-type": "image/png"}).json()
    # the table fits its own conventions to its rounding (plus the candidates' tolerance)
    assert ok["diagnosis"] is None and ok["fit"]["residual_rms"] <= 0.5 / 65535 + 1e-5
    # and its error map after bilinear lookup is the one /lut states for the same table
    lookup = _get(client, kind="split_sum", size=SIZE, quantisation="unorm16", per_texel="false").json()
    assert np.allclose(ok["error"]["max"], list(lookup["error"]["lookup"]["max"].values()), atol=2e-5)
    for name, wrong in {"roughness_direction": samples[::-1], "axis_order": samples.transpose(1, 0, 2),
                        "channels": samples[..., [1, 0, 2]]}.items():
        out = client.post("/api/v1/lut/check?kind=split_sum", content=png.write(wrong, 16),
                          headers={"content-type": "image/png"}).json()
        assert set(out["differs"]) == {name} and name in out["diagnosis"], out["diagnosis"]


def test_json_upload_in_0_255_is_named(client):
    table = np.array(_get(client, kind="kc_E", size=SIZE, quantisation="unorm8").json()["values"])
    out = client.post("/api/v1/lut/check?kind=kc_E", content=json.dumps({"values": (table * 255).tolist()}))
    assert out.status_code == 200 and "0–255" in out.json()["diagnosis"]


def test_exports_say_what_they_hold(client):
    for fmt in ("csv", "c", "glsl", "hlsl"):
        text = _get(client, kind="dfg_filament", size=4, format=fmt, quantisation="float16").text
        assert "dfg_filament" in text and "roughness" in text and "mu" in text
    csv = _get(client, kind="kc_E", size=4, format="csv", quantisation="float32").text
    rows = [line for line in csv.splitlines() if not line.startswith("#")]
    assert rows[0].split(",") == ["i_roughness", "i_mu", "roughness", "mu", "E"] and len(rows) == 17
    z = zipfile.ZipFile(io.BytesIO(_get(client, kind="split_sum", size=4, format="f16", quantisation="float16").content))
    side = json.loads(z.read("lut.json"))
    raw = np.frombuffer(z.read("lut.f16"), "<f2").reshape(side["shape"])
    table = np.array(_get(client, kind="split_sum", size=4, quantisation="float16").json()["values"])
    assert np.array_equal(raw.astype(float), table)


@pytest.mark.parametrize("query, param", [
    ({"kind": "banana"}, "kind"), ({"kind": "split_sum", "size": 100000}, "size"),
    ({"kind": "split_sum", "mu_axis": "theta"}, "mu_axis"),
    ({"kind": "split_sum", "roughness_axis": "sigma"}, "roughness_axis"),
    ({"kind": "split_sum", "quantisation": "unorm4"}, "quantisation"),
    ({"kind": "split_sum", "format": "png", "quantisation": "float16"}, "format"),
    ({"kind": "split_sum", "format": "f16", "quantisation": "unorm16"}, "format"),
    ({"kind": "kc_E_avg", "mu_axis": "mu"}, "mu_axis"),
    ({"kind": "split_sum", "ndf": "blinn_phong"}, "masking")])
def test_bad_lut_queries_are_422_naming_the_parameter(client, query, param):
    res = client.get(f"/api/v1/lut?{urlencode(query)}")
    assert res.status_code == 422, res.text
    assert res.json()["detail"][0]["loc"][-1] == param


@pytest.mark.parametrize("body", [b"\x89PNG\r\n\x1a\nnot a png", b"{\"values\": [[1, 2], [3, 4]]}",
                                  b"{\"values\": \"x\"}", b"\x00\x01", b"{\"values\": [[[0.1, NaN]]]}"])
def test_malformed_upload_is_a_422(client, body):
    res = client.post("/api/v1/lut/check?kind=split_sum", content=body)
    assert res.status_code == 422, res.text
    # the body, or (a NaN in the JSON) the place in it: ["body", "values", 0, 0, 1]
    assert res.json()["detail"][0]["loc"][0] == "body"
