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


def write(samples: np.ndarray, bits: int) -> bytes:
    """``samples`` (rows, columns, 1 or 3) of integers in [0, 2^bits − 1]."""
    rows, cols, channels = samples.shape
    colour = {1: 0, 3: 2}[channels]
    dtype = ">u2" if bits == 16 else "u1"
    raw = np.ascontiguousarray(samples.astype(dtype)).reshape(rows, -1).view(np.uint8)
    lines = np.concatenate([np.zeros((rows, 1), np.uint8), raw], axis=1)   # filter 0 (None)
    header = struct.pack(">IIBBBBB", cols, rows, bits, colour, 0, 0, 0)
    return (SIGNATURE + _chunk(b"IHDR", header) + _chunk(b"IDAT", zlib.compress(lines.tobytes(), 9))
            + _chunk(b"IEND", b""))


def read(data: bytes) -> tuple[np.ndarray, int]:
    """(samples (rows, columns, channels) as integers, bit depth)."""
    if not data.startswith(SIGNATURE):
        raise PngError("not a PNG file (signature missing)")
    pos, header, idat = len(SIGNATURE), None, []
    while pos + 8 <= len(data):
        length, kind = struct.unpack(">I4s", data[pos:pos + 8])
        body = data[pos + 8:pos + 8 + length]
        if len(body) != length:
            raise PngError("truncated chunk")
        if kind == b"IHDR":
            header = struct.unpack(">IIBBBBB", body)
        elif kind == b"IDAT":
            idat.append(body)
        elif kind == b"IEND":
            break
        pos += 12 + length
    if header is None or not idat:
        raise PngError("no IHDR or IDAT chunk")
    cols, rows, bits, colour, _, _, interlace = header
    if bits not in (8, 16) or colour not in COLOUR_CHANNELS or interlace:
        raise PngError(f"unsupported PNG: bit depth {bits}, colour type {colour}, interlace {interlace} "
                       "(8 or 16 bits, grey/RGB with or without alpha, not interlaced)")
    channels = COLOUR_CHANNELS[colour]
    bpp = channels * bits // 8
    stride = cols * bpp
    try:
        raw = zlib.decompress(b"".join(idat))
    except zlib.error as exc:
        raise PngError(f"corrupt image data: {exc}") from None
    if len(raw) != rows * (stride + 1):
        raise PngError("image data does not match the header's size")
    lines = np.frombuffer(raw, np.uint8).reshape(rows, stride + 1)
    out = np.zeros((rows, stride), np.int32)
    prev = np.zeros(stride, np.int32)
    for r in range(rows):
        out[r] = _unfilter(int(lines[r, 0]), lines[r, 1:].astype(np.int32), prev, bpp)
        prev = out[r]
    pixels = out.astype(np.uint8)
    if bits == 16:
        pixels = pixels.reshape(rows, -1, 2)
        values = pixels[..., 0].astype(np.int64) * 256 + pixels[..., 1]
    else:
        values = pixels.astype(np.int64)
    return values.reshape(rows, cols, channels), bits


def _unfilter(kind: int, line: np.ndarray, prev: np.ndarray, bpp: int) -> np.ndarray:
    if kind == 0:
        return line
    if kind == 2:
        return (line + prev) & 0xFF
    if kind not in (1, 3, 4):
        raise PngError(f"unknown scanline filter {kind}")
    out = line.copy()
    for i in range(line.size):           # Sub, Average, Paeth depend on the decoded left byte
        left = out[i - bpp] if i >= bpp else 0
        up = prev[i]
        if kind == 1:
            pred = left
        elif kind == 3:
            pred = (left + up) >> 1
        else:
            upleft = prev[i - bpp] if i >= bpp else 0
            p = left + up - upleft
            pa, pb, pc = abs(p - left), abs(p - up), abs(p - upleft)
            pred = left if pa <= pb and pa <= pc else up if pb <= pc else upleft
        out[i] = (line[i] + pred) & 0xFF
    return out
