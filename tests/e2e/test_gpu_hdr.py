"""Radiance .hdr environments (app/environment/hdr.py, POST /api/v1/environments/hdr):
files written here by a small independent encoder (frexp-based RGBE, flat, old and new
run-length scanlines), read back to RGBE's precision; every malformation a 4xx naming
it. No browser: the upload route runs in the app in process."""
from __future__ import annotations

import math

import numpy as np
import pytest
from fastapi.testclient import TestClient

from app.environment import hdr
from app.main import create_app


def rgbe(rgb) -> bytes:
    """Ward's encoding: the largest channel's frexp exponent shared, mantissas × 256."""
    m = max(rgb)
    if m < 1e-32:
        return bytes(4)
    mant, exp = math.frexp(m)
    scale = mant * 256.0 / m
    return bytes([int(c * scale) for c in rgb] + [exp + 128])


def encode(image: np.ndarray, form: str = "rle", top_down: bool = True) -> bytes:
    h, w, _ = image.shape
    head = b"#?RADIANCE\n# written by the test\nFORMAT=32-bit_rle_rgbe\nEXPOSURE=1.0\n\n"
    head += (b"-Y" if top_down else b"+Y") + f" {h} +X {w}\n".encode()
    rows = image if top_down else image[::-1]
    out = bytearray(head)
    for row in rows:
        px = [rgbe(p) for p in row]
        if form == "flat":
            out += b"".join(px)
        elif form == "old":                      # a pixel, then its repeats as one 1 1 1 n (n < 256)
            i = 0
            while i < w:
                j = i + 1
                while j < w and j - i < 256 and px[j] == px[i]:
                    j += 1
                out += px[i] + (bytes([1, 1, 1, j - i - 1]) if j - i > 1 else b"")
                i = j
        else:                                    # new RLE: channel by channel, runs of equal bytes
            out += bytes([2, 2, w >> 8, w & 0xFF])
            for ch in range(4):
                vals = [p[ch] for p in px]
                i = 0
                while i < w:
                    j = i
                    while j < w and j - i < 127 and vals[j] == vals[i]:
                        j += 1
                    if j - i >= 3:
                        out += bytes([128 + (j - i), vals[i]])
                        i = j
                    else:                        # a short literal (one or two bytes)
                        lit = vals[i:min(w, i + 2)]
                        out += bytes([len(lit)]) + bytes(lit)
                        i += len(lit)
    return bytes(out)


@pytest.fixture(scope="module")
def image():
    rng = np.random.default_rng(3)
    img = np.exp(rng.normal(0, 2, (16, 40, 3))).astype(np.float64)
    img[3:6, 10:30] = [0.5, 0.25, 4.0]            # runs for the run-length forms
    img[0, :] = 0.0                               # E = 0
    return img


@pytest.mark.parametrize("form", ["flat", "old", "rle"])
@pytest.mark.parametrize("top_down", [True, False])
def test_reads_back_to_rgbe_precision(image, form, top_down):
    got = hdr.read_hdr(encode(image, form, top_down))
    assert got.shape == image.shape and got.dtype == np.float32
    # RGBE keeps 8 bits of mantissa against 2^e > the pixel's largest channel m ≥ 2^(e−1),
    # truncated: the error is below one unit, 2^(e−8) ≤ m·2^-7
    peak = image.max(axis=-1, keepdims=True)
    assert np.all(np.abs(got - image) <= peak * 2.0 ** -7)
    assert np.all(got[0] == 0.0)


@pytest.fixture(scope="module")
def client():
    return TestClient(create_app())


def test_upload_describes_the_map(client, image):
    res = client.post("/api/v1/environments/hdr", content=encode(image),
                      headers={"Content-Type": "application/octet-stream"})
    assert res.status_code == 200, res.text
    body = res.json()
    assert (body["width"], body["height"]) == (40, 16)
    bound = (image.max(axis=-1) * 2.0 ** -7).mean()          # each pixel's RGBE bound, averaged
    assert np.all(np.abs(np.array(body["mean_rgb"]) - image.reshape(-1, 3).mean(axis=0)) <= bound)


@pytest.mark.parametrize("data, status, words", [
    (b"\x89PNG\r\n\x1a\n" + bytes(100), 422, "#?RADIANCE"),
    (b"#?RADIANCE\nFORMAT=32-bit_rle_xyze\n\n-Y 2 +X 2\n" + bytes(16), 422, "FORMAT"),
    (b"#?RADIANCE\n\n+X 2 -Y 2\n" + bytes(16), 422, "resolution line"),
    (b"#?RADIANCE\n\n-Y 4 +X 4\n" + bytes(20), 422, "cut short"),
    (b"#?RADIANCE\n\n-Y 100000 +X 100000\n", 413, "at most"),
    (b"#?RADIANCE\nno end of header", 422, "empty line"),
])
def test_bad_files_are_4xx_naming_why(client, data, status, words):
    res = client.post("/api/v1/environments/hdr", content=data)
    assert res.status_code == status, res.text
    assert words in res.text and "file" in res.text


def test_over_the_byte_limit_is_413(client, monkeypatch):
    from app.api.routes import environments
    monkeypatch.setattr(environments, "MAX_FILE_BYTES", 1000)
    res = client.post("/api/v1/environments/hdr", content=b"#?RADIANCE\n" + bytes(2000))
    assert res.status_code == 413 and "1000" in res.text


def _integral(cells: np.ndarray) -> np.ndarray:
    """∫ L dω over the sphere of an equirectangular map (rows from θ = 0), cell by cell:
    each row's solid angle 2π (cos θ_top − cos θ_bottom) shared by its columns."""
    h, w, _ = cells.shape
    edges = np.linspace(0.0, np.pi, h + 1)
    omega = 2 * np.pi * (np.cos(edges[:-1]) - np.cos(edges[1:])) / w
    return np.einsum("ijc,i->c", cells.astype(np.float64), omega)


def test_cells_for_the_gpu_keep_the_maps_integral_and_its_layout():
    rng = np.random.default_rng(5)
    img = np.exp(rng.normal(0, 1.5, (48, 96, 3)))
    cells = hdr.equirect_cells(img, 24)
    assert cells.shape == (12, 24, 3) and cells.dtype == np.float32
    np.testing.assert_allclose(_integral(cells), _integral(img), rtol=1e-6)
    sky = np.zeros((32, 64, 3))
    sky[:16] = 1.0                                   # the upper hemisphere (θ < 90°) only
    sky[:16, 32:] = 2.0                              # twice as bright where φ > 0 (x > 0)
    got = hdr.equirect_cells(sky, 16)
    assert got.shape == (8, 16, 3)
    assert np.all(got[:4, :8] == 1.0) and np.all(got[:4, 8:] == 2.0) and np.all(got[4:] == 0.0)
    assert hdr.equirect_cells(img, 4096).shape == img.shape          # never more cells than pixels


def test_upload_answers_the_cells_as_float32(client, image):
    res = client.post("/api/v1/environments/hdr?format=f32&map_width=20", content=encode(image))
    assert res.status_code == 200, res.text
    h, w, c = (int(x) for x in res.headers["X-Map-Shape"].split(","))
    cells = np.frombuffer(res.content, dtype="<f4").reshape(h, w, c)
    assert (h, w, c) == (8, 20, 3)                   # 16 × 40: blocks of 2 × 2 (8 ≤ 20/2)
    read = hdr.read_hdr(encode(image))
    np.testing.assert_allclose(_integral(cells), _integral(read), rtol=1e-5)
    bad = client.post("/api/v1/environments/hdr?format=f32&map_width=4", content=encode(image))
    assert bad.status_code == 422 and "map_width" in bad.text


def test_reference_slice_directions_are_the_half_and_difference_angles(client):
    """The slice's float32 directions (environments.slice_directions) checked from their
    definition: h = (l + v)/|l + v| is θ_h from the normal, l is θ_d from h (Rusinkiewicz
    1998), at the pixel centres 90°·(k + ½)/n; and the route's bad n is a 422 naming n."""
    from app.api.routes.environments import slice_directions
    n = 16
    l, v = slice_directions(n, 0.0, 90.0)
    h = (l + v) / np.linalg.norm(l + v, axis=1, keepdims=True)
    centres = 90.0 * (np.arange(n) + 0.5) / n
    theta_d, theta_h = (a.ravel() for a in np.meshgrid(centres, centres, indexing="ij"))
    np.testing.assert_allclose(np.degrees(np.arccos(np.clip(h[:, 2], -1, 1))), theta_h, atol=2e-4)
    np.testing.assert_allclose(np.degrees(np.arccos(np.clip(np.sum(l * h, axis=1), -1, 1))), theta_d, atol=2e-4)
    res = client.get("/api/v1/reference/slice?n=4")
    assert res.status_code == 422 and "n" in res.json()["detail"][0]["loc"]
    ok = client.get("/api/v1/reference/slice?n=8&alpha=0.3")
    assert ok.status_code == 200 and len(ok.content) == 8 * 8 * 3 * 8
