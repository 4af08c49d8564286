"""Radiance `.hdr` (RGBE) images: the environment maps users bring.

The format (Ward, "Real Pixels", Graphics Gems II, 1991; the Radiance file format notes):
a text header starting ``#?RADIANCE`` (or ``#?RGBE``), ``KEY=value`` lines with
``FORMAT=32-bit_rle_rgbe``, an empty line, a resolution line ``-Y H +X W`` (rows from the
top; ``+Y`` from the bottom), then H scanlines of W pixels of 4 bytes (R, G, B, shared
exponent E), each scanline flat, in the old run-length form (a pixel ``1 1 1 n`` repeats
the previous one n·256^k times), or in the new per-channel form (``2 2 W_hi W_lo``, then
for each channel runs: a byte c > 128 repeats the next byte c − 128 times, c ≤ 128 copies
c literal bytes). A pixel is (R, G, B)·2^(E − 136), 0 where E = 0 (Ward's rgbe.c).

Every malformation is a :class:`HdrError` naming what is wrong; images over the limits a
:class:`~app.errors.TooLarge`.
"""
from __future__ import annotations

import numpy as np

from ..errors import ParameterError, TooLarge

#: Largest side accepted: an 8K equirectangular map (8192 × 4096) and no more.
MAX_SIDE = 8192
#: Largest pixel count: 8192 × 2048, an 8K-wide map at half its usual height or a 4K one
#: (4096 × 2048) twice over; read as float32 RGB it holds 200 MB.
MAX_PIXELS = 8192 * 2048
#: Largest file: every pixel flat (4 bytes) and a header.
MAX_FILE_BYTES = 4 * MAX_PIXELS + 64 * 1024
#: The new run-length form applies to scanlines of this width (the format's own bounds).
RLE_MIN_WIDTH, RLE_MAX_WIDTH = 8, 0x7FFF
#: The header's longest accepted size: real headers are a few hundred bytes.
MAX_HEADER_BYTES = 64 * 1024
MAGICS = (b"#?RADIANCE", b"#?RGBE")
FORMATS = (b"32-bit_rle_rgbe",)


class HdrError(ParameterError):
    """A file that is not a readable Radiance .hdr: 422 naming the field ``file``."""

    def __init__(self, message: str):
        super().__init__("file", f"not a readable Radiance .hdr: {message}", status=422, loc="body")


def _header(data: bytes) -> tuple[int, int, bool, int]:
    """(height, width, rows from the top, offset of the pixels)."""
    if not data.startswith(MAGICS):
        raise HdrError("it does not start with #?RADIANCE or #?RGBE")
    end = data.find(b"\n\n", 0, MAX_HEADER_BYTES)
    if end < 0:
        raise HdrError(f"no empty line ends its header within {MAX_HEADER_BYTES} bytes")
    for line in data[:end].split(b"\n")[1:]:
        if line.startswith(b"FORMAT=") and line[7:].strip() not in FORMATS:
            raise HdrError(f"FORMAT={line[7:].strip().decode(errors='replace')}: only 32-bit_rle_rgbe is read")
    eol = data.find(b"\n", end + 2)
    if eol < 0:
        raise HdrError("no resolution line after the header")
    words = data[end + 2:eol].split()
    if len(words) != 4 or words[0] not in (b"-Y", b"+Y") or words[2] != b"+X":
        raise HdrError(f"resolution line {data[end + 2:eol][:40]!r}: only -Y H +X W and +Y H +X W are read")
    try:
        height, width = int(words[1]), int(words[3])
    except ValueError:
        raise HdrError("its resolution is not two integers") from None
    if height < 1 or width < 1:
        raise HdrError(f"its size {width}×{height} is empty")
    if max(height, width) > MAX_SIDE or height * width > MAX_PIXELS:
        raise TooLarge("file", f"{width}×{height} pixels: at most {MAX_SIDE} per side and {MAX_PIXELS} in all",
                       loc="body")
    return height, width, words[0] == b"-Y", eol + 1


def _scanline(buf: memoryview, pos: int, width: int, previous: np.ndarray | None) -> tuple[np.ndarray, int]:
    """One scanline's RGBE bytes (width, 4) and the position after it."""
    n = len(buf)
    if RLE_MIN_WIDTH <= width <= RLE_MAX_WIDTH and pos + 4 <= n and buf[pos] == 2 and buf[pos + 1] == 2 \
            and not buf[pos + 2] & 0x80:
        if (buf[pos + 2] << 8 | buf[pos + 3]) != width:
            raise HdrError(f"a run-length scanline says width {buf[pos + 2] << 8 | buf[pos + 3]}, the image {width}")
        pos += 4
        line = np.empty((4, width), dtype=np.uint8)
        for ch in range(4):
            x = 0
            while x < width:
                if pos >= n:
                    raise HdrError("the pixels end inside a scanline (the file is cut short)")
                count = buf[pos]
                pos += 1
                if count > 128:
                    count -= 128
                    if x + count > width or pos >= n:
                        raise HdrError("a run goes past the end of its scanline")
                    line[ch, x:x + count] = buf[pos]
                    pos += 1
                else:
                    if count == 0 or x + count > width or pos + count > n:
                        raise HdrError("a literal run is empty or goes past its scanline")
                    line[ch, x:x + count] = np.frombuffer(buf[pos:pos + count], dtype=np.uint8)
                    pos += count
                x += count
        return line.T, pos
    # flat pixels, with the old run-length form (1 1 1 n: repeat the previous pixel)
    line = np.empty((width, 4), dtype=np.uint8)
    x, shift = 0, 0
    last = previous[-1] if previous is not None else None
    while x < width:
        if pos + 4 > n:
            raise HdrError("the pixels end inside a scanline (the file is cut short)")
        px = buf[pos:pos + 4]
        pos += 4
        if px[0] == 1 and px[1] == 1 and px[2] == 1:
            if last is None:
                raise HdrError("a repeat before any pixel")
            count = px[3] << shift
            if x + count > width:
                raise HdrError("a repeat goes past the end of its scanline")
            line[x:x + count] = last
            x += count
            shift += 8
            continue
        last = np.frombuffer(px, dtype=np.uint8)
        line[x] = last
        x += 1
        shift = 0
    return line, pos


def read_hdr(data: bytes) -> np.ndarray:
    """The image as float32 radiance (height, width, 3), row 0 at the top."""
    height, width, top_down, pos = _header(data)
    buf = memoryview(data)
    rgbe = np.empty((height, width, 4), dtype=np.uint8)
    previous = None
    for row in range(height):
        rgbe[row], pos = _scanline(buf, pos, width, previous)
        previous = rgbe[row]
    if not top_down:
        rgbe = rgbe[::-1]
    e = rgbe[..., 3].astype(np.int32)
    scale = np.where(e > 0, np.ldexp(np.float32(1.0), e - 136), 0.0).astype(np.float32)
    return rgbe[..., :3].astype(np.float32) * scale[..., None]


def _factor(n: int, most: int) -> int:
    """The smallest divisor k of n with n / k ≤ most: cells of k whole source pixels."""
    return next(k for k in range(1, n + 1) if n % k == 0 and n // k <= max(1, most))


def equirect_cells(image: np.ndarray, width: int) -> np.ndarray:
    """The equirectangular ``image`` (H, W, 3; rows from the top, θ from 0 to π) averaged
    onto at most ``width`` × ``width``/2 cells, each a whole block of source pixels (the
    block sides divide H and W, so every cell is an exact band of θ and φ; never more
    cells than pixels): the block's mean with rows weighted by their solid angle
    (∝ cos θ_top − cos θ_bottom), so the cells' radiance times their solid angle sums to
    the source's integral over the sphere. float32."""
    h_src, w_src, _ = image.shape
    fc = _factor(w_src, int(width))
    fr = _factor(h_src, int(width) // 2)
    h, w = h_src // fr, w_src // fc
    edges = np.linspace(0.0, np.pi, h_src + 1)
    omega = (np.cos(edges[:-1]) - np.cos(edges[1:])).reshape(h, fr)          # each source row's share
    blocks = image.astype(np.float64).reshape(h, fr, w, fc, 3).mean(axis=3)   # (h, fr, w, 3)
    weighted = np.einsum("irjc,ir->ijc", blocks, omega) / omega.sum(axis=1)[:, None, None]
    return weighted.astype(np.float32)
