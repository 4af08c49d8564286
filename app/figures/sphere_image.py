"""The rendered sphere as a picture: linear radiance → exposure (×2^EV) → the sRGB
transfer curve (IEC 61966-2-1) → 8-bit, as a PNG in a Plotly image figure (the
``sphere_env`` view) or as 0–255 integers (``/materials/sphere``). The one sRGB encode."""
from __future__ import annotations

import base64

import numpy as np

from ..lut import png
from .style import model_title


def srgb_encode(linear) -> np.ndarray:
    """The sRGB transfer function (IEC 61966-2-1) of values clipped to [0, 1]."""
    c = np.clip(np.asarray(linear, dtype=float), 0.0, 1.0)
    small = c <= 0.0031308
    return np.where(small, 12.92 * c, 1.055 * np.power(c, 1 / 2.4, where=~small, out=np.zeros_like(c)) - 0.055)


def srgb8(radiance, background, exposure_ev: float = 0.0) -> np.ndarray:
    """(n, n, 3) linear radiance, NaN off the sphere, over ``background`` (an (n, n, 3)
    image or one colour; linear) as 0–255 sRGB integers."""
    image = np.where(np.isnan(radiance), np.asarray(background, dtype=float), radiance)
    return np.round(srgb_encode(2.0 ** exposure_ev * image) * 255.0).astype(np.int64)


def srgb8_sphere(data: dict) -> dict:
    """{"rgb": the sphere on white as 0–255 sRGB integers (values above 1 clipped),
    "max": the largest value before clipping}."""
    return {"rgb": srgb8(data["radiance"], 1.0), "max": float(np.nanmax(data["radiance"], initial=0.0))}


def caption(data: dict) -> str:
    """What the picture is an estimate of: its samples and stated noise (none for delta
    lights). Never a timing: the same query gives the same caption."""
    noise = data.get("noise")
    if not noise:
        return "point light: no sampling, no noise"
    return (f"{data['samples']['per_pixel']} samples/pixel, noise ±{100 * noise['relative']:.1f}% "
            "(RMS of the pixels' standard errors / mean)")


def environment_sphere_figure(data: dict, spec: dict, lighting_label: str, exposure_ev: float) -> dict:
    """The sphere over the environment behind it, titled with the model (its material)
    and the lighting; the sampling and its noise in the subtitle."""
    encoded = base64.b64encode(png.write(srgb8(data["radiance"], data["background"], exposure_ev), 8)).decode()
    n = data["radiance"].shape[0]
    title = f"{model_title(spec)} under {lighting_label}"
    return {"data": [{"type": "image", "source": f"data:image/png;base64,{encoded}",
                      "x0": -1.0 + 1.0 / n, "dx": 2.0 / n, "y0": 1.0 - 1.0 / n, "dy": -2.0 / n,
                      "hoverinfo": "skip"}],
            "layout": {"title": {"text": f"{title}<br><sub>{caption(data)}</sub>"},
                       "xaxis": {"visible": False, "scaleanchor": "y"},
                       "yaxis": {"visible": False, "autorange": "reversed"},
                       "margin": {"l": 10, "r": 10, "t": 60, "b": 10}}}
