"""Measured materials drive the page's model: chosen in the model menu or given as
`material=` in a link, every panel draws the material's Fresnel (issue 34).

The reference is the exact conductor Fresnel of the material's own RGB n, k (GET
/api/v1/materials), written here from its definition (Born & Wolf §14.2: the s and p
amplitudes of a complex index) and averaged over the hemisphere by quadrature: nothing of
the server's Fresnel code.
"""
from __future__ import annotations

import base64
import json
import re
import urllib.request
from urllib.parse import parse_qs, urlparse

import numpy as np
import pytest

from test_page import wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

#: luminance of linear sRGB (Rec. 709 / sRGB primaries, ITU-R BT.709 Y row)
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def material(base_url: str, slug: str) -> dict:
    with urllib.request.urlopen(f"{base_url}/api/v1/materials") as res:
        return next(m for m in json.load(res)["materials"] if m["slug"] == slug)


def conductor_fresnel(mu: np.ndarray, n: float, k: float) -> np.ndarray:
    """Unpolarised reflectance of a conductor n + ik from air at cos θ = mu."""
    eta = complex(n, k)
    cos_t = np.sqrt(1 - (1 - mu**2) / eta**2 + 0j)
    rs = (mu - eta * cos_t) / (mu + eta * cos_t)
    rp = (eta * mu - cos_t) / (eta * mu + cos_t)
    return (abs(rs) ** 2 + abs(rp) ** 2) / 2


def hemispherical_average(n: float, k: float) -> float:
    """F̄ = 2 ∫₀¹ F(μ) μ dμ by Gauss-Legendre on [0, 1]."""
    x, w = np.polynomial.legendre.leggauss(64)
    mu = (x + 1) / 2
    return float(np.sum(w / 2 * 2 * conductor_fresnel(mu, n, k) * mu))


def sent(log, view: str) -> list[dict[str, str]]:
    out = []
    for url in log.requests:
        u = urlparse(url)
        if u.path == f"/api/v1/figures/{view}":
            out.append({k: v[-1] for k, v in parse_qs(u.query).items()})
    return out


def curve(page, view: str) -> tuple[str, np.ndarray, np.ndarray]:
    """The first curve a panel draws: its name and its points (arrays as sent, plain or
    Plotly's typed {dtype, bdata})."""
    t = page.evaluate(f"() => {{ const t = document.getElementById('plot-{view}').data[0];"
                      " return {name: t.name, x: t.x, y: t.y}; }")

    def array(a):
        if isinstance(a, dict):
            return np.frombuffer(base64.b64decode(a["bdata"]), dtype=np.dtype(a["dtype"]).newbyteorder("<"))
        return np.asarray(a, dtype=float)
    return t["name"], array(t["x"]), array(t["y"])


def check_fresnel_panel(page, base_url: str, slug: str) -> None:
    """The Fresnel panel draws the material's F: F(0) and F̄ (named in its legend)."""
    m = material(base_url, slug)
    f0 = float(LUMINANCE @ [conductor_fresnel(np.array([1.0]), n, k)[0] for n, k in zip(m["n"], m["k"])])
    f_avg = float(LUMINANCE @ [hemispherical_average(n, k) for n, k in zip(m["n"], m["k"])])
    name, theta, f = curve(page, "fresnel")
    assert theta[0] == 0 and f[0] == pytest.approx(f0, rel=1e-3)
    assert float(re.search(r"F̄ = ([0-9.]+)", name).group(1)) == pytest.approx(f_avg, rel=1e-3)


def test_a_copper_link_drives_every_panel(page, page_log, base_url):
    views = ("lobe", "ndf", "g1", "albedo", "fresnel", "sphere", "slice")
    page.goto(f"/?material=copper&show={','.join(views)}")
    wait_quiet(page, [f"plot-{v}" for v in views], timeout=60_000)
    # nothing says the link was ignored: the notice is not shown
    assert page.locator("#notice").is_hidden(), page.locator("#notice").text_content()
    # the model menu says copper; the Fresnel menu is the material's, not choosable
    assert page.input_value("#model") == "material:copper"
    assert page.locator("#fresnel").is_disabled()
    assert "Copper" in page.locator("#fresnel-info").text_content()
    assert page.locator("#f0").is_hidden()
    for view in views:
        q = sent(page_log, view)[-1]
        assert q.get("material") == "copper" and "fresnel" not in q and "f0" not in q, (view, q)
    check_fresnel_panel(page, base_url, "copper")
    assert page_log.problems() == []


def test_the_model_menu_sets_a_material_and_the_link_keeps_it(page, page_log, base_url):
    page.goto("/?show=lobe,fresnel")
    wait_quiet(page, ["plot-lobe", "plot-fresnel"])
    options = page.locator("#model option").evaluate_all("(os) => os.map((o) => o.value)")
    assert len([o for o in options if o.startswith("material:")]) >= 100    # 110 measured materials
    page.select_option("#model", "material:gold")
    page.wait_for_function("() => new URLSearchParams(location.search).get('material') === 'gold'")
    wait_quiet(page, ["plot-lobe", "plot-fresnel"])
    assert "material=gold" in page.url and "fresnel=" not in page.url
    check_fresnel_panel(page, base_url, "gold")
    # the link opens the same page
    page.goto(page.url)
    wait_quiet(page, ["plot-lobe", "plot-fresnel"])
    assert page.input_value("#model") == "material:gold"
    assert page.locator("#notice").is_hidden()
    # back to the Fresnel menu: no material in the link or the requests
    page.select_option("#model", "microfacet")
    page.wait_for_function("() => !new URLSearchParams(location.search).has('material')")
    wait_quiet(page, ["plot-lobe", "plot-fresnel"])
    assert "material" not in sent(page_log, "lobe")[-1]
    assert page.locator("#fresnel").is_enabled()
    assert page_log.problems() == []


def test_a_misspelt_material_is_said_with_a_suggestion(page, page_log):
    page.goto("/?material=Gold&show=lobe")
    wait_quiet(page, ["plot-lobe"])
    notice = page.locator("#notice").text_content()
    assert "material=Gold" in notice and "gold" in notice and "Unknown parameter" not in notice
    assert page.input_value("#model") == "microfacet"
    assert page_log.problems() == []
