"""The LUT upload's PNG reader: the size refused from IHDR before anything is inflated,
inflation bounded by what the header declares, every scanline filter undone exactly
(16-bit RGB included), and deep JSON refused with a 4xx (issue 36).

The PNGs here are written by this file's own writer (zlib + struct, the forward filters
of ISO/IEC 15948 §9.2 written out per byte), independent of app/lut/png.py.
"""
from __future__ import annotations

import struct
import time
import tracemalloc
import zlib

import numpy as np
import pytest

from app.lut import png
from tests.datasets.conftest import client, app  # noqa: F401  (fixtures)

#: what a refusal may cost (issue 36's bar)
SECONDS, BYTES = 0.5, 50 * 1024 * 1024


def _chunk(kind: bytes, body: bytes) -> bytes:
    return struct.pack(">I", len(body)) + kind + body + struct.pack(">I", zlib.crc32(kind + body))


def _png(width: int, height: int, bits: int, colour: int, idat: bytes) -> bytes:
    ihdr = struct.pack(">IIBBBBB", width, height, bits, colour, 0, 0, 0)
    return b"\x89PNG\r\n\x1a\n" + _chunk(b"IHDR", ihdr) + _chunk(b"IDAT", idat) + _chunk(b"IEND", b"")


def _zeros_deflated(inflated: int, piece: int = 1 << 20) -> bytes:
    """A zlib stream of ``inflated`` zero bytes, made from one flushed piece repeated (a
    full flush resets the compressor, so every identical piece compresses identically)."""
    c = zlib.compressobj(9)
    head = c.compress(bytes(piece)) + c.flush(zlib.Z_FULL_FLUSH)
    middle = c.compress(bytes(piece)) + c.flush(zlib.Z_FULL_FLUSH)
    return head + middle * (inflated // piece - 1) + c.flush()


def _posted(client, body: bytes):
    """(answer, seconds, peak bytes traced) of posting ``body``, after one small request
    that warms the app (its first request builds what every later one shares)."""
    client.post("/api/v1/lut/check?kind=split_sum", content=b"\x89PNG\r\n\x1a\n",
                headers={"content-type": "image/png"})
    tracemalloc.start()
    start = time.perf_counter()
    res = client.post("/api/v1/lut/check?kind=split_sum", content=body,
                      headers={"content-type": "image/png"})
    seconds = time.perf_counter() - start
    peak = tracemalloc.get_traced_memory()[1]
    tracemalloc.stop()
    return res, seconds, peak


def test_a_png_declaring_8000_by_8000_is_refused_from_its_header(client):
    body = _png(8000, 8000, 8, 2, _zeros_deflated(8000 * (8000 * 3 + 1) // 4))
    assert 40_000 < len(body) < 100_000          # the 62 KB file, give or take
    res, seconds, peak = _posted(client, body)
    assert res.status_code == 422, res.text
    detail = res.json()["detail"][0]
    assert detail["loc"][-1] == "body" and "8000 × 8000" in detail["msg"] and "256" in detail["msg"]
    assert seconds < SECONDS and peak < BYTES, (seconds, peak)


def test_a_png_inflating_past_its_header_is_refused_without_inflating_it(client):
    """A 256 × 256 header (allowed) over ~1 MB of deflate that inflates to ~1 GB."""
    body = _png(256, 256, 16, 2, _zeros_deflated(1 << 30))
    assert 500_000 < len(body) < 2_000_000
    res, seconds, peak = _posted(client, body)
    assert res.status_code == 422, res.text
    assert "256 × 256" in res.json()["detail"][0]["msg"]
    assert seconds < SECONDS and peak < BYTES, (seconds, peak)


def _filtered(raw: np.ndarray, bpp: int) -> bytes:
    """Scanlines of ``raw`` (rows, bytes) filtered with None, Sub, Up, Average, Paeth in
    turn, row by row: ISO/IEC 15948 §9.2–9.4 written out byte by byte."""
    rows, width = raw.shape
    out = bytearray()
    prev = [0] * width
    for r in range(rows):
        kind = r % 5
        line = [int(x) for x in raw[r]]
        out.append(kind)
        for i in range(width):
            a = line[i - bpp] if i >= bpp else 0
            b = prev[i]
            c = prev[i - bpp] if i >= bpp else 0
            if kind == 0:
                pred = 0
            elif kind == 1:
                pred = a
            elif kind == 2:
                pred = b
            elif kind == 3:
                pred = (a + b) // 2
            else:
                p = a + b - c
                pa, pb, pc = abs(p - a), abs(p - b), abs(p - c)
                pred = a if pa <= pb and pa <= pc else (b if pb <= pc else c)
            out.append((line[i] - pred) % 256)
        prev = line
    return bytes(out)


@pytest.mark.parametrize("bits, colour, channels", [(16, 2, 3), (8, 2, 3), (16, 0, 1), (8, 6, 4)])
def test_every_filter_is_undone_exactly(bits, colour, channels):
    rng = np.random.default_rng(bits + colour)
    width, height = 23, 17
    samples = rng.integers(0, 2 ** bits, (height, width, channels))
    samples[3:6] = samples[2]                # flat and smooth runs, where filters matter
    samples[:, 5] = 2 ** bits - 1
    raw = samples.astype(">u2" if bits == 16 else "u1").reshape(height, -1).view(np.uint8)
    bpp = channels * bits // 8
    body = _png(width, height, bits, colour, zlib.compress(_filtered(raw, bpp)))
    got, got_bits = png.read(body)
    assert got_bits == bits and got.shape == samples.shape
    assert np.array_equal(got, samples)


def test_a_deeply_nested_json_body_is_a_422(client):
    for body in (b"[" * 100_000 + b"]" * 100_000, b'{"values": ' + b"[" * 5000 + b"]" * 5000 + b"}"):
        res = client.post("/api/v1/lut/check?kind=split_sum", content=body,
                          headers={"content-type": "application/json"})
        assert res.status_code == 422, res.text
        assert res.json()["detail"][0]["loc"][-1] == "body"
