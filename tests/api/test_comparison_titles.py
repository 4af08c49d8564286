"""A comparison figure's title says what is compared, not the API's description of the
view: POST /figures/ndf with two models was titled 'D(θ_m) at azimuth φ, θ_m = 0..90°:
2 models' (issue 11), and GET with vary likewise names the varied values."""
from __future__ import annotations

import pytest

BODY = {"models": [{"ndf": "ggx", "alpha": 0.2}, {"ndf": "beckmann", "alpha": 0.2}]}


@pytest.mark.parametrize("kind", ["ndf", "lobe", "albedo"])
def test_comparison_title_names_what_is_compared(client, kind):
    one = client.get(f"/api/v1/figures/{kind}?alpha=0.2")
    both = client.post(f"/api/v1/figures/{kind}", json=BODY)
    assert one.status_code == both.status_code == 200, both.text
    summary = next(v["summary"] for v in client.get("/api/v1/views").json() if v["name"] == kind)
    _names_the_models(both.json()["layout"]["title"]["text"], summary)
    # the quantity named as in the single figure's own title, before its " — "
    quantity = one.json()["layout"]["title"]["text"].split(" — ")[0]
    assert both.json()["layout"]["title"]["text"].startswith(quantity)
    varied = client.get(f"/api/v1/figures/{kind}?alpha=0.2&vary=ndf&values=ggx,beckmann")
    assert varied.status_code == 200, varied.text
    _names_the_models(varied.json()["layout"]["title"]["text"], summary)


def _names_the_models(title: str, summary: str) -> None:
    assert "ggx" in title and "beckmann" in title, title
    assert "models" not in title and summary.split(":")[0] not in title, title
