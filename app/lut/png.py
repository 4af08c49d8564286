"""PNG without an imaging library: write 8- or 16-bit grey/RGB, read what LUTs use.

PNG (ISO/IEC 15948): signature, IHDR, IDAT (zlib of scanlines, each led by a filter
byte), IEND; each chunk length, type, data, CRC-32. 16-bit samples are big-endian.
The reader takes bit depths 8 and 16, colour types grey (0), grey+alpha (4), RGB (2)
and RGBA (6), no interlace, and undoes the five scanline filters.
"""
from __future__ import annotations

import struct
import zlib

import numpy as np

SIGNATURE = b"\x89PNG\r\n\x1a\n"
COLOUR_CHANNELS = {0: 1, 2: 3, 4: 2, 6: 4}


class PngError(ValueError):
    pass


def _chunk(kind: bytes, data: bytes) -> bytes:
    return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data) & 0xFFFFFFFF)


def text_chunk(keyword: str, text: str) -> bytes:
    """An iTXt chunk (ISO/IEC 15948 §11.3.4.5): keyword (Latin-1, 1–79 bytes), then
    uncompressed UTF-8 text with no language tag; image viewers and ``exiftool`` show it."""
    key = keyword.encode("latin-1")
    if not 1 <= len(key) <= 79:
        raise ValueError(f"a PNG text keyword has 1-79 bytes; got {keyword!r}")
    return _chunk(b"iTXt", key + b"\x00\x00\x00" + b"\x00" + b"\x00" + text.encode("utf-8"))


def texts(data: bytes) -> dict[str, str]:
    """The iTXt chunks of ``data`` (uncompressed ones) as {keyword: text}."""
    out, pos = {}, len(SIGNATURE)
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if kind == b"iTXt":
            key, _, rest = body.partition(b"\x00")
            if rest[:1] == b"\x00":                      # not compressed
                _, _, rest = rest[2:].partition(b"\x00")  # language tag
                _, _, text = rest.partition(b"\x00")      # translated keyword
                out[key.decode("latin-1")] = text.decode("utf-8", "replace")
        pos += 12 + length
    return out


def write(samples: np.ndarray, bits: int, text: dict[str, str] | None = None) -> bytes:
    """``samples`` (rows, columns, 1 or 3) of integers in [0, 2^bits − 1]; ``text``:
    {keyword: text} written as iTXt chunks before the image data."""
    rows, cols, channels = samples.shape
    colour = {1: 0, 3: 2}[channels]
    dtype = ">u2" if bits == 16 else "u1"
    raw = np.ascontiguousarray(samples.astype(dtype)).reshape(rows, -1).view(np.uint8)
    lines = np.concatenate([np.zeros((rows, 1), np.uint8), raw], axis=1)   # filter 0 (None)
    header = struct.pack(">IIBBBBB", cols, rows, bits, colour, 0, 0, 0)
    notes = b"".join(text_chunk(k, v) for k, v in (text or {}).items())
    return (SIGNATURE + _chunk(b"IHDR", header) + notes + _chunk(b"IDAT", zlib.compress(lines.tobytes(), 9))
            + _chunk(b"IEND", b""))


class PngSizeError(PngError):
    """The header declares a width or height outside what the caller accepts: refused
    from IHDR, before a byte of image data is inflated."""


def header(data: bytes) -> tuple[int, int, int, int]:
    """(width, height, bit depth, colour type) from IHDR, which PNG requires to be the
    first chunk (ISO/IEC 15948 §5.6); nothing else is read."""
    if not data.startswith(SIGNATURE):
        raise PngError("not a PNG file (signature missing)")
    start = len(SIGNATURE)
    if len(data) < start + 8 + 13 or data[start + 4:start + 8] != b"IHDR":
        raise PngError("the first chunk is not IHDR")
    cols, rows, bits, colour, _, _, interlace = struct.unpack(">IIBBBBB", data[start + 8:start + 21])
    if bits not in (8, 16) or colour not in COLOUR_CHANNELS or interlace:
        raise PngError(f"unsupported PNG: bit depth {bits}, colour type {colour}, interlace {interlace} "
                       "(8 or 16 bits, grey/RGB with or without alpha, not interlaced)")
    return cols, rows, bits, colour


def read(data: bytes, max_side: int | None = None) -> tuple[np.ndarray, int]:
    """(samples (rows, columns, channels) as integers, bit depth).

    The size is checked from IHDR first (``max_side`` bounds width and height), and
    inflation is bounded by the size the header declares, so a small file declaring a huge
    image or inflating to more than its header says costs no more than its own size."""
    cols, rows, bits, colour = header(data)
    if max_side is not None and not (1 <= cols <= max_side and 1 <= rows <= max_side):
        raise PngSizeError(f"the PNG is {cols} × {rows} pixels (width × height); width and height "
                           f"must be in [1, {max_side}]")
    idat, pos = [], len(SIGNATURE)
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        if pos + 12 + length > len(data):
            raise PngError("truncated chunk")
        if kind == b"IDAT":
            idat.append(data[pos + 8:pos + 8 + length])
        elif kind == b"IEND":
            break
        pos += 12 + length
    if not idat:
        raise PngError("no IDAT chunk")
    channels = COLOUR_CHANNELS[colour]
    bpp = channels * bits // 8
    stride = cols * bpp
    expected = rows * (stride + 1)
    inflate = zlib.decompressobj()
    try:
        raw = inflate.decompress(b"".join(idat), expected + 1)   # one byte more shows an excess
    except zlib.error as exc:
        raise PngError(f"corrupt image data: {exc}") from None
    if len(raw) != expected:
        raise PngError(f"the image data inflate to {'more' if len(raw) > expected else len(raw)} "
                       f"bytes; the header's {cols} × {rows} pixels need {expected}")
    lines = np.frombuffer(raw, np.uint8).reshape(rows, stride + 1)
    kinds = lines[:, 0]
    if kinds.max() > 4:
        raise PngError(f"unknown scanline filter {int(kinds.max())} (0–4 are defined)")
    pixels = _unfilter(kinds, lines[:, 1:].reshape(rows, cols, bpp))
    if bits == 16:
        values = pixels.reshape(rows, cols, channels, 2).astype(np.int64)
        values = values[..., 0] * 256 + values[..., 1]
    else:
        values = pixels.reshape(rows, cols, channels).astype(np.int64)
    return values, bits


def _paeth(a: np.ndarray, b: np.ndarray, c: np.ndarray) -> np.ndarray:
    """The Paeth predictor (ISO/IEC 15948 §9.4): of left a, up b, upper-left c, the one
    nearest to a + b − c, ties to a, then b."""
    p = a + b - c
    pa, pb, pc = np.abs(p - a), np.abs(p - b), np.abs(p - c)
    return np.where((pa <= pb) & (pa <= pc), a, np.where(pb <= pc, b, c))


def _unfilter(kinds: np.ndarray, filtered: np.ndarray) -> np.ndarray:
    """Undo the scanline filters (ISO/IEC 15948 §9.2) of ``filtered`` (rows, columns,
    bytes per pixel), each row's filter in ``kinds``.

    A byte depends on its left, upper and upper-left neighbours once they are decoded,
    so the pixels on one anti-diagonal (row + column = k) depend only on earlier ones:
    one vectorised step per anti-diagonal (rows + columns − 1 steps) undoes every filter
    at once. The decoded image is padded with a zero row above and a zero column to the
    left, which are the "missing neighbour" values the standard prescribes."""
    rows, cols, bpp = filtered.shape
    out = np.zeros((rows + 1, cols + 1, bpp), np.int32)
    line = filtered.astype(np.int32)
    for k in range(rows + cols - 1):
        r = np.arange(max(0, k - cols + 1), min(rows, k + 1))
        c = k - r
        x = line[r, c]
        a, b, up_left = out[r + 1, c], out[r, c + 1], out[r, c]
        kind = kinds[r][:, None]
        pred = np.select([kind == 1, kind == 2, kind == 3, kind == 4],
                         [a, b, (a + b) >> 1, _paeth(a, b, up_left)], 0)
        out[r + 1, c + 1] = (x + pred) & 0xFF
    return out[1:, 1:].astype(np.uint8)
