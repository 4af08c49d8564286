"""GET /api/v1/lut builds the Schlick-GGX tables engines ship (k = α/2 for image-based
light, k = (r + 1)²/8 for direct light; Karis 2013), checked against the test's own
quadrature (reference_split_sum.py) and against the closed form at α → 0."""
from __future__ import annotations

import numpy as np
import pytest

from app.lut import png
from tests.lut.reference_split_sum import k_direct, k_ibl, split_sum_integrals

N = 8
#: the reference's own error at μ ≥ 1/16 (doubling its nodes moves E by ≤ 2e-5 there)
#: plus the table's (float32, its quadrature to 1e-6)
TOL = 1e-4


@pytest.mark.parametrize("masking, k_of", [("schlick_ibl", k_ibl), ("schlick_direct", k_direct)])
@pytest.mark.parametrize("g2", ["separable", "height_correlated"])
def test_schlick_ggx_split_sum_matches_an_independent_quadrature(client, masking, k_of, g2):
    res = client.get(f"/api/v1/lut?kind=split_sum&size={N}&masking={masking}&g2={g2}&quantisation=float32"
                     "&per_texel=false")
    assert res.status_code == 200, res.text
    body = res.json()
    assert f"masking={masking}" in body["model"] and f"g2={g2}" in body["model"]
    assert "Schlick-GGX" in body["model_label"]
    values = np.array(body["values"])
    r = np.array(body["axes"][0]["values"])
    mu = np.array(body["axes"][1]["values"])
    for i in range(N):
        e1, es = split_sum_integrals(r[i] ** 2, mu, g2, k_of=k_of)
        assert np.allclose(values[i], np.stack([e1 - es, es], axis=-1), atol=TOL, rtol=0), (i, values[i])


def test_split_sum_at_vanishing_roughness_is_schlicks_fresnel(client):
    """As α → 0 the lobe is a mirror (h = n, v·h = μ) and G → 1, so scale → 1 − (1 − μ)⁵
    and bias → (1 − μ)⁵ (Schlick 1994). At the first row (r = 1/64, α = r²): Schlick-GGX's
    1 − G ≤ k(1 − μ_l)/μ_l + k(1 − μ)/μ, and v·h departs from μ by O(α), which moves
    (1 − v·h)⁵ by ≤ 5α: the tolerance 2k/μ + 5α."""
    n = 32
    body = client.get(f"/api/v1/lut?kind=split_sum&size={n}&masking=schlick_ibl&g2=separable"
                      "&quantisation=float32&per_texel=false").json()
    mu = np.array(body["axes"][1]["values"])
    alpha = np.array(body["axes"][0]["values"])[0] ** 2
    row = np.array(body["values"])[0]
    fresnel = (1.0 - mu) ** 5
    tol = 2 * (alpha / 2) / mu + 5 * alpha
    keep = mu > 0.1                       # where the bound is tight enough to say something
    assert np.all(np.abs(row[keep, 0] - (1.0 - fresnel[keep])) <= tol[keep])
    assert np.all(np.abs(row[keep, 1] - fresnel[keep]) <= tol[keep])


def test_png_states_the_model_it_was_built_for(client):
    res = client.get(f"/api/v1/lut?kind=dfg_filament&size=4&masking=schlick_direct&format=png")
    text = png.texts(res.content)
    assert text["BRDF-model"].startswith("ndf=ggx&masking=schlick_direct")
    assert "(r+1)²/8" in text["BRDF-model-label"] and "dfg_filament" in text["Description"]
