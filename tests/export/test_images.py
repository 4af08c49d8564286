"""SVG and PNG exports rendered by kaleido in one headless Chromium for the session;
and the 503 (with what to install) where no Chromium is found."""
from __future__ import annotations

import struct
import xml.etree.ElementTree as ET
import zlib
from concurrent.futures import ThreadPoolExecutor

import pytest

from app.views import VIEWS
from tests.budget import settings_for_tests
from app.export.image import ImageRenderer, get_renderer
from app.main import create_app

from .conftest import TestClient

SVG_NS = "{http://www.w3.org/2000/svg}"
SMALL = {"n": 9, "n_theta": 9, "n_phi": 13}


def small_query(kind: str) -> dict:
    fields = VIEWS[kind].figure_query.model_fields
    return {k: v for k, v in SMALL.items() if k in fields}


def png_size(data: bytes) -> tuple[int, int]:
    """Width and height from the IHDR chunk, after checking that the image data inflates to
    exactly height rows of (filter byte + width × bytes per pixel)."""
    assert data[:8] == b"\x89PNG\r\n\x1a\n"
    length, kind = struct.unpack(">I4s", data[8:16])
    assert kind == b"IHDR" and length == 13
    width, height, depth, colour = struct.unpack(">IIBB", data[16:26])
    channels = {0: 1, 2: 3, 4: 2, 6: 4}[colour]
    pos, idat = 8, b""
    while pos < len(data):
        n, k = struct.unpack(">I4s", data[pos:pos + 8])
        if k == b"IDAT":
            idat += data[pos + 8:pos + 8 + n]
        pos += 12 + n
    assert len(zlib.decompress(idat)) == height * (1 + width * channels * depth // 8)
    return width, height


@pytest.mark.e2e
@pytest.mark.parametrize("kind", list(VIEWS))
def test_svg_of_every_view_parses(image_client, kind):
    r = image_client.get(f"/api/v1/figures/{kind}.svg", params={**small_query(kind), "width": 640, "height": 400})
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == "image/svg+xml"
    assert f'filename="{kind}' in r.headers["content-disposition"]
    root = ET.fromstring(r.content)
    assert root.tag == f"{SVG_NS}svg"
    assert (root.get("width"), root.get("height")) == ("640", "400")
    texts = " ".join("".join(t.itertext()) for t in root.iter(f"{SVG_NS}text"))  # tspans too
    assert texts.strip()                       # titles and tick labels were drawn


@pytest.mark.e2e
@pytest.mark.parametrize("kind, width, height, scale", [("lobe", 500, 300, 2.0), ("sphere", 400, 400, 1.0)])
def test_png_has_the_asked_size(image_client, kind, width, height, scale):
    r = image_client.get(f"/api/v1/figures/{kind}.png",
                         params={**small_query(kind), "width": width, "height": height, "scale": scale})
    assert r.status_code == 200, r.text
    assert r.headers["content-type"] == "image/png"
    assert png_size(r.content) == (round(width * scale), round(height * scale))


@pytest.mark.e2e
def test_concurrent_exports_each_get_their_own_image(image_client):
    widths = [300, 340, 380, 420]

    def get(w):
        return w, image_client.get("/api/v1/figures/ndf.png", params={"n": 9, "width": w, "height": 200})

    with ThreadPoolExecutor(4) as pool:
        for w, r in pool.map(get, widths):
            assert r.status_code == 200 and png_size(r.content) == (w, 200)


@pytest.mark.e2e
def test_overlay_exports_as_svg(image_client):
    r = image_client.get("/api/v1/figures/albedo.svg?n=3&vary=alpha&values=0.2,0.8")
    assert r.status_code == 200
    texts = " ".join(t.text or "" for t in ET.fromstring(r.content).iter(f"{SVG_NS}text"))
    assert "alpha=0.2" in texts and "alpha=0.8" in texts


def test_no_chromium_is_503_saying_what_to_install():
    missing = ImageRenderer(browser_path="/nonexistent/chromium")
    app = create_app(settings_for_tests())
    app.dependency_overrides[get_renderer] = lambda: missing
    client = TestClient(app)
    for ext in ("svg", "png"):
        r = client.get(f"/api/v1/figures/lobe.{ext}")
        assert r.status_code == 503
        assert int(r.headers["retry-after"]) >= 1
        (error,) = r.json()["detail"]
        msg = error["msg"]
        assert "apt-get install chromium" in msg and "/nonexistent/chromium" in msg
    assert client.get("/api/v1/figures/lobe.csv").status_code == 200     # CSV needs no browser


@pytest.mark.parametrize("params, name", [
    ({"width": 4096, "height": 4096, "scale": 2}, "scale"),     # 4096²·4 > BRDF_MAX_EXPORT_PIXELS
    ({"width": 50}, "width"), ({"height": 5000}, "height"), ({"scale": 0}, "scale"),
])
def test_image_size_limits_are_422(client, params, name):
    r = client.get("/api/v1/figures/lobe.png", params=params)
    assert r.status_code == 422
    assert r.json()["detail"][0]["loc"][-1] == name
