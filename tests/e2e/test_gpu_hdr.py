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
