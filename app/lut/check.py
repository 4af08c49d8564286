"""An uploaded LUT against the reference: its error map, and whether it looks flipped,
transposed, channel-swapped or stored 0–255.

The upload is compared with the reference as given and under each rearrangement a
shader bug would cause (flip of either axis, transpose, both, channels swapped). If one
of those fits at least DIAGNOSIS_RATIO times better than the table as given, the answer
names it.
"""
from __future__ import annotations

import json

import numpy as np

from ..errors import ParameterError
from . import png
from .build import SIZE_MAX, SIZE_MIN

#: a rearrangement is reported when its max error is this many times below the as-given one
DIAGNOSIS_RATIO = 4.0
#: JSON nesting accepted: an object holding [i][j][c] is 4 deep; deeper is refused before
#: parsing (a recursive parser would otherwise exhaust its stack on "[[[[…")
MAX_JSON_DEPTH = 8


def json_depth(body: bytes) -> int:
    """The deepest nesting of ``[``/``{`` in ``body``, counting brackets inside strings too
    (an over-estimate only for strings holding brackets, which a LUT body has none of)."""
    raw = np.frombuffer(body, np.uint8)
    step = (np.isin(raw, (ord("["), ord("{"))).astype(np.int64)
            - np.isin(raw, (ord("]"), ord("}"))))
    return int(np.cumsum(step).max(initial=0))


def parse(body: bytes, content_type: str, channels: int, dims: int) -> np.ndarray:
    """The uploaded values as floats [rows][columns][channels] (or [rows][channels]): a
    PNG (8 or 16 bits; RG tables in R and G) or JSON ``{"values": [i][j][c]}``."""
    if body.startswith(png.SIGNATURE) or content_type.startswith("image/png"):
        try:
            samples, bits = png.read(body, max_side=SIZE_MAX)
        except png.PngSizeError as exc:
            raise ParameterError("body", f"{exc}: a LUT is n × n (kc_E_avg: 1 × n) with n in "
                                         f"[{SIZE_MIN}, {SIZE_MAX}]", loc="body") from None
        except png.PngError as exc:
            raise ParameterError("body", f"malformed PNG: {exc}", loc="body") from None
        if samples.shape[-1] < channels:
            raise ParameterError("body", f"the PNG has {samples.shape[-1]} channel(s); this kind has {channels}",
                                 loc="body")
        values = samples[..., :channels] / float(2 ** bits - 1)
        if dims == 1 and values.shape[0] == 1:
            values = values[0]
    else:
        depth = json_depth(body)
        if depth > MAX_JSON_DEPTH:
            raise ParameterError("body", f"the JSON body nests {depth} deep; a LUT is "
                                         f'{{"values": [i][j][c]}}, at most {MAX_JSON_DEPTH} deep',
                                 loc="body")
        try:
            data = json.loads(body)
            values = np.asarray(data["values"] if isinstance(data, dict) else data, dtype=float)
        except (ValueError, KeyError, TypeError):
            raise ParameterError("body", 'the body must be a PNG or JSON {"values": [i][j][c]} of numbers',
                                 loc="body") from None
        if values.ndim == dims:           # one channel given without its own axis
            values = values[..., None]
    n = values.shape[0] if values.ndim else 0
    shape = (n,) * dims + (channels,)
    if values.shape != shape or not SIZE_MIN <= n <= SIZE_MAX:
        raise ParameterError("body", f"the uploaded LUT has shape {list(values.shape)}; this kind needs "
                                     f"{['n'] * dims + [channels]} with n in [{SIZE_MIN}, {SIZE_MAX}] "
                                     "([rows][columns][channels])", loc="body")
    if not np.all(np.isfinite(values)):
        raise ParameterError("body", "the uploaded LUT holds non-finite values", loc="body")
    return values


def _candidates(values: np.ndarray, dims: int) -> dict[str, np.ndarray]:
    out = {"as given": values}
    if dims == 2:
        out.update({"flipped along axes[0] (upside down)": values[::-1],
                    "flipped along axes[1]": values[:, ::-1],
                    "transposed (axes swapped)": values.transpose(1, 0, 2),
                    "transposed and flipped": values.transpose(1, 0, 2)[::-1],
                    "rotated by 180°": values[::-1, ::-1]})
    else:
        out["reversed"] = values[::-1]
    if values.shape[-1] == 2:
        out.update({f"{k}, channels swapped" if k != "as given" else "channels swapped": v[..., ::-1]
                    for k, v in list(out.items())})
    if values.max() > 1.5:
        out["stored 0–255"] = values / 255.0
    return out


def compare(values: np.ndarray, reference: np.ndarray, bound: np.ndarray, dims: int) -> dict:
    """Error map of the upload (as given) and the best-fitting rearrangement."""
    fits = {name: float(np.max(np.abs(v - reference))) for name, v in _candidates(values, dims).items()}
    best = min(fits, key=fits.get)
    given = fits["as given"]
    diagnosis = None
    if best != "as given" and fits[best] * DIAGNOSIS_RATIO < given:
        diagnosis = f"this looks {best}: max error {fits[best]:.3g} that way, {given:.3g} as given"
    err = np.abs(values - reference)
    return {"error": {"per_texel": err, "max": err.max(axis=tuple(range(dims))),
                      "reference_bound": bound.max(axis=tuple(range(dims)))},
            "diagnosis": diagnosis, "fits": fits}
