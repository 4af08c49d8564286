"""GET /api/v1/conventions, its figure, and the D/G α consistency check."""
from __future__ import annotations

import math

import numpy as np
import pytest

from app.model import make_spec
from tests.shader import reference_albedo


def _rows(client, **query):
    res = client.get("/api/v1/conventions", params=query)
    assert res.status_code == 200, res.text
    return {row["ecosystem"]: row for row in res.json()}


def test_every_ecosystem_answers_with_its_alpha(client):
    rows = _rows(client, roughness=0.5)
    assert {"Disney (Burley 2012)", "glTF 2.0", "Filament", "UE4, D (GGX)", "UE4, G direct light",
            "UE4, G image-based light", "pbrt-v3", "pbrt-v4", "Blender Principled (Burley map)",
            "OpenPBR Surface"} <= set(rows)
    for row in rows.values():
        assert set(row) >= {"ecosystem", "alpha", "note"} and row["note"]
    for name in ("Disney (Burley 2012)", "glTF 2.0", "Filament", "UE4, D (GGX)", "OpenPBR Surface"):
        assert rows[name]["alpha"] == pytest.approx(0.25)          # α = r²
    assert rows["pbrt-v4"]["alpha"] ** 2 == pytest.approx(0.5)    # α = √r
    # Karis 2013: k = (r + 1)²/8 for direct light, r²/2 = α/2 for image-based light
    assert rows["UE4, G direct light"]["k"] == pytest.approx(2.25 / 8)
    assert rows["UE4, G image-based light"]["k"] == pytest.approx(0.125)


def test_pbrt_v3_polynomial_and_out_of_range_notes(client):
    # pbrt-v3's RoughnessToAlpha at r = 1 is its constant term 1.62142 (x = ln 1 = 0): above 1
    row = _rows(client, roughness=1.0)["pbrt-v3"]
    assert row["alpha"] == pytest.approx(1.62142) and "outside" in row["note"]
    # below r = 1e-3 it is clamped: the same α at 1e-4 and 1e-3
    assert _rows(client, roughness=1e-4)["pbrt-v3"]["alpha"] == _rows(client, roughness=1e-3)["pbrt-v3"]["alpha"]
    tiny = _rows(client, roughness=0.005)
    assert "outside" in tiny["glTF 2.0"]["note"]                 # α = 2.5e-5 < 1e-4
    assert tiny["Filament"]["alpha"] == pytest.approx(0.045 ** 2)  # Filament's clamp
    assert "outside" not in _rows(client, roughness=0.5)["glTF 2.0"]["note"]


def test_anisotropy_maps(client):
    rows = _rows(client, roughness=0.6, anisotropy=0.5)
    burley = rows["Blender Principled (Burley map)"]
    assert burley["alpha"] * burley["alpha_y"] == pytest.approx(0.6 ** 4)   # aspect, 1/aspect
    assert burley["alpha"] / burley["alpha_y"] == pytest.approx(1 / (1 - 0.45))
    openpbr = rows["OpenPBR Surface"]
    assert openpbr["alpha_y"] == pytest.approx(0.5 * openpbr["alpha"])
    assert openpbr["alpha"] == pytest.approx(0.36 * math.sqrt(2 / 1.25))


@pytest.mark.parametrize("query", [{"roughness": 1.5}, {"roughness": -0.1}, {"roughness": "nan"},
                                   {"roughness": 0.5, "anisotropy": 2}])
def test_out_of_range_is_a_422_naming_it(client, query):
    res = client.get("/api/v1/conventions", params=query)
    assert res.status_code == 422
    name = res.json()["detail"][0]["loc"][-1]
    assert name in query and "[0, 1]" in res.json()["detail"][0]["msg"]


def test_figure_has_every_lobe(client):
    fig = client.get("/api/v1/conventions/figure", params={"roughness": 0.3, "anisotropy": 0.4}).json()
    lobes = [t for t in fig["data"] if t["type"] == "scatter"]
    assert len(lobes) == len(_rows(client, roughness=0.3))


class _MismatchedLobe:
    """GGX with D at α and height-correlated G2 from Λ at α_G (closed form, Heitz 2014
    eq. 86, 99), F = 1: written here, not by the code under test."""

    def __init__(self, alpha, alpha_G):
        self.ndf = make_spec(ndf="ggx", alpha=alpha).brdf().ndf
        self.alpha_G = alpha_G

    def _lam(self, w):
        mu = w[..., 2]
        t2 = np.maximum(1 - mu * mu, 0) / np.maximum(mu * mu, 1e-300)
        return 0.5 * (np.sqrt(1 + self.alpha_G ** 2 * t2) - 1)

    def evaluate(self, l, v, want):
        G2 = np.where((l[..., 2] > 0) & (v[..., 2] > 0), 1 / (1 + self._lam(l) + self._lam(v)), 0.0)
        return {"G2": G2, "F": np.ones_like(G2)}


def test_consistency_check_flags_and_measures(client):
    ok = client.get("/api/v1/conventions/check", params={"alpha": 0.3, "alpha_G": 0.3, "fresnel": "none"}).json()
    assert ok["consistent"] and ok["flag"] is None and ok["max_E_difference"] < 1e-12  # two code paths
    bad = client.get("/api/v1/conventions/check",
                     params={"alpha": 0.3, "alpha_G": 0.6, "fresnel": "none", "n": 5}).json()
    assert not bad["consistent"] and "0.6" in bad["flag"]
    # E(μ = 0.5) of the mismatched model against an independent quadrature of it
    mu = bad["mu"].index(0.5)
    ref, ref_err = reference_albedo.albedo(_MismatchedLobe(0.3, 0.6), 0.5)
    assert abs(bad["E_mismatched"][mu] - ref) <= bad["E_error"][mu] + ref_err
    assert bad["E_avg_difference"] < 0          # more masking, less energy
