"""MERL ``.binary`` measured BRDFs (Matusik et al. 2003, "A Data-Driven Reflectance
Model"; the layout and indexing of the published reader, ``BRDFRead.cpp``).

A file is three little-endian int32 dimensions (90, 90, 180) followed by the R, G and B
tables of doubles, each in (θ_h, θ_d, φ_d) order (φ_d fastest). Cell (i, j, k) covers
θ_h ∈ [90°(i/90)², 90°((i+1)/90)²) (θ_h indexed by √(θ_h/90°): fine near the specular
peak), θ_d ∈ [j°, (j+1)°), φ_d ∈ [k°, (k+1)°). Only φ_d ∈ [0, 180°) is stored: swapping
l and v maps φ_d to φ_d + 180° (reciprocity, with isotropy), so a lookup folds φ_d onto
that half, as the reader does. A stored value times its channel's scale is f in 1/sr;
a negative entry means "not measured".

Angles inside are radians; the half/difference angles are Rusinkiewicz 1998's.
"""
from __future__ import annotations

import numpy as np

from ..errors import ParameterError
from ..physics.vectors import half_vector

DIMS = (90, 90, 180)                      # θ_h, θ_d, φ_d cells
CELLS = DIMS[0] * DIMS[1] * DIMS[2]
#: f = stored value × scale, per channel R, G, B (the published reader's constants)
SCALES = np.array([1.0 / 1500.0, 1.15 / 1500.0, 1.66 / 1500.0])
HEADER_BYTES = 12
FILE_BYTES = HEADER_BYTES + 3 * CELLS * 8  # 34 992 012
#: the stored value of a cell that was not measured (any negative value means that)
NOT_MEASURED = -1.0


#: header dimensions up to this are taken for a MERL-like file with the wrong dimensions
PLAUSIBLE_DIM = 100_000


def looks_like(content: bytes) -> bool:
    """The header is three positive int32 dimensions (MERL's, or plausibly a table of
    other dimensions, which :func:`read` then names)."""
    if len(content) < HEADER_BYTES:
        return False
    dims = np.frombuffer(content[:HEADER_BYTES], "<i4")
    return tuple(dims) == DIMS or bool(((dims > 0) & (dims <= PLAUSIBLE_DIM)).all())


def read(content: bytes) -> np.ndarray:
    """The table f[channel, θ_h, θ_d, φ_d] in 1/sr (negative = not measured), from a
    file's bytes; a ParameterError naming what is wrong with a bad file."""
    if len(content) < HEADER_BYTES:
        raise ParameterError("file", f"a MERL .binary file starts with three int32 dimensions "
                                     f"(12 bytes); this one has {len(content)} bytes", loc="body")
    dims = tuple(int(x) for x in np.frombuffer(content[:HEADER_BYTES], "<i4"))
    if dims != DIMS:
        raise ParameterError("file", f"MERL dimensions must be {DIMS[0]} × {DIMS[1]} × {DIMS[2]} "
                                     f"(θ_h, θ_d, φ_d); the header says {dims[0]} × {dims[1]} × "
                                     f"{dims[2]}", loc="body")
    if len(content) != FILE_BYTES:
        what = "truncated" if len(content) < FILE_BYTES else "longer than its tables"
        raise ParameterError("file", f"a MERL .binary file of {DIMS[0]} × {DIMS[1]} × {DIMS[2]} "
                                     f"cells has exactly {FILE_BYTES} bytes; this one has "
                                     f"{len(content)} ({what})", loc="body")
    raw = np.frombuffer(content, "<f8", offset=HEADER_BYTES).reshape(3, *DIMS)
    bad = ~np.isfinite(raw)
    if bad.any():
        c, i, j, k = (int(x[0]) for x in np.nonzero(bad))
        raise ParameterError("file", f"MERL values must be finite (negative marks a cell not "
                                     f"measured); channel {'RGB'[c]} cell (θ_h {i}, θ_d {j}, "
                                     f"φ_d {k}) is {raw[c, i, j, k]}", loc="body")
    return raw * SCALES[:, None, None, None]


def write(table: np.ndarray) -> bytes:
    """The bytes of a MERL file of ``table`` (f[channel, θ_h, θ_d, φ_d] in 1/sr, negative =
    not measured), the inverse of :func:`read`."""
    raw = np.where(table >= 0, table / SCALES[:, None, None, None], NOT_MEASURED)
    return np.asarray(DIMS, "<i4").tobytes() + np.ascontiguousarray(raw, "<f8").tobytes()


def half_diff(l, v):
    """(θ_h, θ_d, φ_d) in radians of direction pairs, φ_d in (−π, π], and where h exists.

    h = (l+v)/‖l+v‖; d is l in the frame where h is the pole: l rotated by −φ_h about n,
    then by −θ_h about the bitangent (Rusinkiewicz 1998, sec. 3)."""
    l = np.asarray(l, dtype=float)
    h, exists = half_vector(l, v)
    theta_h = np.arccos(np.clip(h[..., 2], -1.0, 1.0))
    phi_h = np.arctan2(h[..., 1], h[..., 0])
    cp, sp = np.cos(phi_h), np.sin(phi_h)
    x = cp * l[..., 0] + sp * l[..., 1]
    y = -sp * l[..., 0] + cp * l[..., 1]
    ct, st = np.cos(theta_h), np.sin(theta_h)
    dx, dz = x * ct - l[..., 2] * st, x * st + l[..., 2] * ct
    return theta_h, np.arccos(np.clip(dz, -1.0, 1.0)), np.arctan2(y, dx), exists


def cell_of(theta_h, theta_d, phi_d):
    """Cell indices (i, j, k) of half/difference angles (radians), as the published
    reader finds them: i = ⌊√(θ_h/90° · 90²)⌋, j = ⌊θ_d/1°⌋, k = ⌊(φ_d mod 180°)/1°⌋,
    clamped to the table."""
    deg = np.rad2deg
    i = np.sqrt(np.maximum(deg(theta_h), 0.0) * DIMS[0])
    phi = np.where(phi_d < 0.0, phi_d + np.pi, phi_d)
    return (np.clip(i.astype(int), 0, DIMS[0] - 1),
            np.clip(deg(theta_d).astype(int), 0, DIMS[1] - 1),
            np.clip((deg(phi) * DIMS[2] / 180.0).astype(int), 0, DIMS[2] - 1))


def centres_deg():
    """θ_h, θ_d, φ_d (degrees) of the cell centres — the middle of each cell in index
    space (θ_h = 90°((i + ½)/90)²): the angles a model is tabulated at."""
    u = (np.arange(DIMS[0]) + 0.5) / DIMS[0]
    return 90.0 * u * u, np.arange(DIMS[1]) + 0.5, (np.arange(DIMS[2]) + 0.5) * 180.0 / DIMS[2]


def lookup(table: np.ndarray, l, v, stride: int = 1) -> np.ndarray:
    """f[channel, ...] at direction pairs by the reader's nearest-cell rule; negative
    where the cell was not measured or h does not exist (l = −v). ``stride`` > 1: the
    table is every stride-th cell of a full one along each axis (``table[:, ::2, ::2, ::2]``)."""
    theta_h, theta_d, phi_d, exists = half_diff(l, v)
    i, j, k = (np.minimum(x // stride, n - 1) for x, n in zip(cell_of(theta_h, theta_d, phi_d),
                                                              table.shape[1:]))
    return np.where(exists, table[:, i, j, k], NOT_MEASURED)


def lookup_linear(table: np.ndarray, l, v, stride: int = 1) -> np.ndarray:
    """f[channel, ...] interpolated linearly between cell centres in index space (φ_d
    periodic over 180°), where all eight neighbours were measured; the nearest cell
    elsewhere. With ``stride`` as in :func:`lookup`: comparing the full table with every
    other cell estimates the interpolation error."""
    theta_h, theta_d, phi_d, exists = half_diff(l, v)
    deg = np.rad2deg
    coords = [np.sqrt(np.maximum(deg(theta_h), 0.0) * DIMS[0]), deg(theta_d),
              deg(np.where(phi_d < 0.0, phi_d + np.pi, phi_d)) * DIMS[2] / 180.0]
    shape = table.shape[1:]
    lo, frac = [], []
    for axis, u in enumerate(coords):
        u = (u - 0.5 * stride) / stride          # cell centres at whole numbers
        if axis < 2:
            u = np.clip(u, 0.0, shape[axis] - 1.0)
        base = np.floor(u)
        lo.append(base.astype(int))
        frac.append(u - base)
    value = np.zeros((table.shape[0],) + np.shape(theta_h))
    complete = np.ones(np.shape(theta_h), dtype=bool)
    for corner in range(8):
        index, weight = [], 1.0
        for axis in range(3):
            up = (corner >> axis) & 1
            n = shape[axis]
            index.append((lo[axis] + up) % n if axis == 2 else np.minimum(lo[axis] + up, n - 1))
            weight = weight * (frac[axis] if up else 1.0 - frac[axis])
        corner_value = table[:, index[0], index[1], index[2]]
        complete &= (corner_value >= 0).all(axis=0)
        value += weight * corner_value
    return np.where(exists & complete, value, lookup(table, l, v, stride))
