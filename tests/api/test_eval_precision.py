"""POST/GET /api/v1/eval's ``precision``: float64 by default; float32 on request (f only,
GGX models), its dtype and stated error bound in the answer, within that bound of float64;
anything else a 422 naming ``precision``."""
from __future__ import annotations

import numpy as np
import pytest

from app import kernels

BODY = {"alpha": 0.2, "theta_i_deg": [0, 30, 60, 89], "phi_i_deg": [0], "theta_o_deg": [10, 30, 60, 88],
        "phi_o_deg": [180], "quantities": ["f"]}


@pytest.mark.skipif(not kernels.ENABLED, reason="numba absent or BRDF_FAST=0")
def test_float32_on_request_within_its_bound(client):
    r64 = client.post("/api/v1/eval", json=BODY)
    r32 = client.post("/api/v1/eval", json={**BODY, "precision": "float32"})
    assert r64.status_code == 200 and r32.status_code == 200, r32.text
    assert "precision" not in r64.json()          # float64: the answer as before
    body = r32.json()
    assert body["precision"]["dtype"] == "float32"
    bound = body["precision"]["max_rel_error_bound"]
    f64, f32 = np.array(r64.json()["f"]), np.array(body["f"])
    assert np.all(np.abs(f32 - f64) <= bound * f64)
    assert np.array_equal(f32, f32.astype(np.float32))   # float32 values


@pytest.mark.parametrize("extra, needle", [
    ({"precision": "float16"}, "'float64' or 'float32'"),
    ({"precision": "float32", "quantities": ["f", "D"]}, "f only"),
    ({"precision": "float32", "ndf": "beckmann"}, "ndf=ggx only"),
    ({"precision": "float32", "masking": "smith_numeric"}, "masking=smith_numeric"),
])
def test_precision_refused_naming_it(client, extra, needle):
    r = client.post("/api/v1/eval", json={**BODY, **extra})
    assert r.status_code == 422, r.text
    errors = r.json()["detail"]
    assert any(e["loc"] == ["body", "precision"] and needle in e["msg"] for e in errors), errors
    g = client.get("/api/v1/eval", params={"precision": extra["precision"], "quantities": ",".join(extra.get("quantities", ["f"])),
                                           **{k: v for k, v in extra.items() if k not in ("precision", "quantities")}})
    assert g.status_code == 422 and any("precision" in e["loc"] for e in g.json()["detail"]), g.text
