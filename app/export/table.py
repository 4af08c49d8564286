"""The numbers behind a figure as CSV: a header row naming each column with its unit, by
layout rules that hold for every view (so a view added later exports unchanged):

* every array of the payload as long as its first 1-D array is a column ("wide":
  ``theta_deg, D_per_sr``); a list of texts of that length (a row's id or label) too, first;
* an N-D array (N ≥ 2) is a grid: the 1-D arrays are its axes in payload order (rows, then
  columns); the table is "long", one row per point (``theta_deg, phi_deg, f_per_sr``, numpy
  C order); a grid dimension with no axis array of its length gets an index column;
* a colour grid (N ≥ 3, last axis the 3 channels of linear RGB: the lit sphere's radiance)
  is three grids, ``radiance_r_per_sr``, ``_g_``, ``_b_``; a 3-vector beside it (its
  background colour) is a scalar, ``0.02,0.02,0.02``;
* scalars (E_avg, method, timing) and the model and view parameters go above the header as
  ``# name = value`` lines (``pandas.read_csv(comment="#")``, ``numpy.loadtxt`` skip them);
* ±inf (a divergence) and NaN (a gap, e.g. a pixel off the lit sphere) are empty cells:
  CSV has no infinity that every reader agrees on."""
from __future__ import annotations

import csv
import io
from typing import Iterable

import numpy as np

from ..errors import ParameterError

# Units of the quantities the views return, as a column-name suffix. A key that already
# ends in its unit (``theta_deg``) or is dimensionless (G1, Λ, F, E, μ) has none.
PER_SR = "_per_sr"
UNIT_SUFFIX = {
    "D": PER_SR, "D_cos": PER_SR, "f": PER_SR, "f_cos": PER_SR, "pdf": PER_SR,
    "radiance": PER_SR,
    "std_error": PER_SR,      # the lit sphere's per-pixel standard error of its luminance
}



def _not_a_table(reason: str) -> ParameterError:
    """A payload that breaks the layout rules: CSV does not apply to it (422 on the
    request's format)."""
    return ParameterError("format", f"format=csv: this view's data is not a table ({reason})",
                          loc="path")


#: the channels of a colour grid, in the order of its last axis
CHANNELS = ("r", "g", "b")


def column_name(key: str) -> str:
    """``radiance`` → ``radiance_per_sr``; a channel keeps its unit last:
    ``radiance_r`` → ``radiance_r_per_sr``."""
    base, _, channel = key.rpartition("_")
    if channel in CHANNELS and base in UNIT_SUFFIX:
        return f"{base}_{channel}{UNIT_SUFFIX[base]}"
    return key + UNIT_SUFFIX.get(key, "")


def json_key(column: str) -> str:
    """The payload key a CSV column came from (inverse of :func:`column_name`; a
    channel's column gives ``radiance_r``)."""
    for key, suffix in UNIT_SUFFIX.items():
        if column == key + suffix:
            return key
        for channel in CHANNELS:
            if column == f"{key}_{channel}{suffix}":
                return f"{key}_{channel}"
    return column


def _is_array(value) -> bool:
    if isinstance(value, np.ndarray):
        return value.ndim >= 1 and value.dtype.kind in "fiub"
    if isinstance(value, (list, tuple)) and value:
        a = np.asarray(value, dtype=object)
        return a.dtype != object or all(isinstance(x, (int, float, type(None))) for x in a.ravel())
    return False


def _as_float(value) -> np.ndarray:
    if isinstance(value, np.ndarray):
        return value.astype(float)
    return np.array([np.nan if x is None else x for x in np.ravel(np.asarray(value, dtype=object))],
                    dtype=float).reshape(np.shape(value))


def _is_colour_grid(a: np.ndarray) -> bool:
    return a.ndim >= 3 and a.shape[-1] == len(CHANNELS)


def split(payload: dict) -> tuple[dict[str, np.ndarray], dict]:
    """Arrays (as float64) and scalars of a view's payload, in payload order; a colour
    grid becomes one grid per channel, and a 3-vector beside it a scalar (the layout
    rules above)."""
    arrays, scalars = {}, {}
    for key, value in payload.items():
        if _is_array(value):
            arrays[key] = _as_float(value)
        else:
            scalars[key] = value
    if not any(_is_colour_grid(a) for a in arrays.values()):
        return arrays, scalars
    out = {}
    for key, a in arrays.items():
        if _is_colour_grid(a):
            out.update({f"{key}_{c}": a[..., i] for i, c in enumerate(CHANNELS)})
        elif a.shape == (len(CHANNELS),):
            scalars[key] = ",".join(_format_number(x) for x in a)
        else:
            out[key] = a
    return out, scalars


def columns(payload: dict) -> dict[str, np.ndarray]:
    """Payload key → 1-D column, following the layout rules above."""
    arrays, _ = split(payload)
    if not arrays:
        raise _not_a_table("the payload has no arrays")
    grids = {k: a for k, a in arrays.items() if a.ndim >= 2}
    if not grids:
        n = next(iter(arrays.values())).size
        wrong = [k for k, a in arrays.items() if a.size != n]
        if wrong:
            raise _not_a_table(f"columns of unequal length: {', '.join(wrong)}")
        return arrays
    shape = next(iter(grids.values())).shape
    if any(a.shape != shape for a in grids.values()):
        raise _not_a_table("grids of different shapes: " +
                         ", ".join(f"{k}{a.shape}" for k, a in grids.items()))
    axes_left = [(k, a) for k, a in arrays.items() if a.ndim == 1]
    out: dict[str, np.ndarray] = {}
    mesh_axes = []
    for dim, size in enumerate(shape):
        match = next((i for i, (_, a) in enumerate(axes_left) if a.size == size), None)
        if match is None:
            name, values = f"index{dim}", np.arange(size, dtype=float)
        else:
            name, values = axes_left.pop(match)
        mesh_axes.append((name, values))
    if axes_left:
        raise _not_a_table(f"1-D arrays that are not axes of the grid {shape}: "
                         + ", ".join(k for k, _ in axes_left))
    mesh = np.meshgrid(*(v for _, v in mesh_axes), indexing="ij")
    for (name, _), m in zip(mesh_axes, mesh):
        out[name] = m.ravel()
    for k, a in grids.items():
        out[k] = a.ravel()
    return out


def _format_number(x: float) -> str:
    """The shortest text that reads back as the same float64 (Python's repr); empty
    for a divergence or a gap."""
    return repr(float(x)) if np.isfinite(x) else ""


def _format_scalar(v) -> str:
    if isinstance(v, (bool, np.bool_)):
        return "true" if v else "false"
    if isinstance(v, (float, np.floating)):
        return _format_number(v) if np.isfinite(v) else "null"
    return str(v)


def _with_labels(payload: dict) -> dict[str, np.ndarray]:
    """:func:`columns`, preceded by the payload's lists of texts that label its rows (the
    checks' ``id``, the advice's ``label``): a table whose rows are named says which is
    which in the table itself."""
    cols = columns(payload)
    rows = next(iter(cols.values())).size
    labels = {k: np.asarray(v, dtype=object) for k, v in payload.items()
              if isinstance(v, (list, tuple)) and len(v) == rows and v
              and all(isinstance(x, str) for x in v)}
    return {**labels, **cols}


def to_csv(payload: dict, meta: dict | None = None) -> str:
    """CSV text of one payload (see the module docstring for the layout)."""
    cols = _with_labels(payload)
    _, scalars = split(payload)
    return _write(cols, {**(meta or {}), **scalars})


def to_csv_variants(vary: str, payloads: Iterable[tuple[object, dict]], meta: dict | None = None) -> str:
    """CSV of several payloads of one view (an overlay): a first column ``vary`` holds
    the varied parameter's value; scalars are listed per value in the comments. A column
    only some values have (the error of an approximation against the exact form) is
    empty in the rows of the others."""
    blocks, comments = [], dict(meta or {})
    for value, payload in payloads:
        cols = _with_labels(payload)
        _, scalars = split(payload)
        for k, s in scalars.items():
            comments[f"{k} [{vary}={value}]"] = s
        n = next(iter(cols.values())).size
        blocks.append(({vary: np.full(n, value, dtype=object), **cols}))
    names = list(dict.fromkeys(k for b in blocks for k in b))
    merged = {k: np.concatenate([b[k] if k in b else np.full(len(b[vary]), np.nan)
                                 for b in blocks]) for k in names}
    return _write(merged, comments)


def _write(cols: dict[str, np.ndarray], comments: dict) -> str:
    buf = io.StringIO()
    for k, v in comments.items():
        if v is None or isinstance(v, (dict, list, tuple)):
            continue
        buf.write(f"# {k} = {_format_scalar(v)}\n")
    writer = csv.writer(buf, lineterminator="\n")
    names = list(cols)
    writer.writerow([column_name(k) for k in names])
    arrays = [cols[k] for k in names]
    fmt = [(lambda a: [str(x) for x in a]) if a.dtype == object else
           (lambda a: [_format_number(x) for x in a]) for a in arrays]
    text_cols = [f(a) for f, a in zip(fmt, arrays)]
    writer.writerows(zip(*text_cols))
    return buf.getvalue()
