"""base_color as the principled family takes it: "r,g,b" (linear), a JSON list [r, g, b],
or "#rrggbb" / "#rgb" (sRGB-encoded, decoded by the sRGB curve, IEC 61966-2-1)."""
from __future__ import annotations

import math

import numpy as np

from ..errors import ParameterError
from .params import LUMINANCE


def _srgb_decode(c: float) -> float:
    """The sRGB transfer curve's inverse (IEC 61966-2-1): an encoded value to linear."""
    return c / 12.92 if c <= 0.04045 else ((c + 0.055) / 1.055) ** 2.4


def colour_text(value):
    """base_color in any accepted form as the canonical "r,g,b" text (linear): "r,g,b",
    a list [r, g, b], or "#rrggbb" / "#rgb" (sRGB). Anything else: a message that shows
    the forms (pydantic turns the ValueError into a 422 naming base_color)."""
    forms = "give r,g,b (three numbers in [0, 1], e.g. 0.82,0.67,0.16), [r, g, b] in JSON, or #rrggbb"
    if isinstance(value, (list, tuple)):
        if len(value) != 3 or not all(isinstance(x, (int, float)) and not isinstance(x, bool)
                                      for x in value):
            raise ValueError(f"base_color as a list needs three numbers; got {value!r}; {forms}")
        value = ",".join(repr(float(x)) for x in value)
    if not isinstance(value, str):
        raise ValueError(f"base_color {value!r} is not a colour; {forms}")
    text = value.strip()
    if text.startswith("#"):
        digits = text[1:]
        if len(digits) == 3:
            digits = "".join(d * 2 for d in digits)
        try:
            if len(digits) != 6:
                raise ValueError
            rgb = [int(digits[k:k + 2], 16) / 255.0 for k in (0, 2, 4)]
        except ValueError:
            raise ValueError(f"base_color {text!r} is not a hex colour (#rrggbb or #rgb); {forms}") from None
        return ",".join(repr(_srgb_decode(c)) for c in rgb)
    parts = [x.strip() for x in text.split(",")]
    try:
        numbers = [float(x) for x in parts]
    except ValueError:
        numbers = []
    if len(numbers) != 3:
        raise ValueError(f"base_color {text!r} is not three numbers; {forms}")
    return ",".join(parts)



def parse_color(text) -> tuple[float, float, float]:
    """"r,g,b" (or a sequence of three) → three floats in [0, 1]."""
    parts = text.split(",") if isinstance(text, str) else list(text)
    try:
        rgb = tuple(float(x) for x in parts)
    except (TypeError, ValueError):
        rgb = ()
    if len(rgb) != 3 or not all(math.isfinite(c) and 0.0 <= c <= 1.0 for c in rgb):
        raise ParameterError("base_color", f"base_color must be three numbers r,g,b in [0, 1]; got {text!r}")
    return rgb


def channel(rgb: np.ndarray, name: str) -> np.ndarray:
    """One channel of (..., 3), or its Rec. 709 luminance."""
    if name == "luminance":
        return rgb @ np.asarray(LUMINANCE)
    return rgb[..., "rgb".index(name)]
