"""From linear radiance to what the page shows: exposure (EV), the sRGB transfer curve
(IEC 61966-2-1), 8-bit PNG (app/lut/png.py) in a Plotly image figure."""
from __future__ import annotations

import base64

import numpy as np

from ..lut import png


def srgb_encode(x) -> np.ndarray:
    x = np.clip(np.asarray(x, dtype=float), 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1.0 / 2.4) - 0.055)


def to_png(radiance: np.ndarray, background, exposure_ev: float) -> bytes:
    """(n, n, 3) linear radiance (NaN off the sphere → the background) as an sRGB PNG."""
    scale = 2.0 ** exposure_ev
    image = np.where(np.isnan(radiance), np.asarray(background, dtype=float), radiance)
    return png.write(np.round(srgb_encode(scale * image) * 255.0).astype(np.int64), 8)


def sphere_figure(data: dict, exposure_ev: float, title: str) -> dict:
    encoded = base64.b64encode(to_png(data["radiance"], data["background"], exposure_ev)).decode()
    noise = data.get("noise")
    caption = (f"{data['samples']['per_pixel']} samples/pixel, noise ±{100 * noise['relative']:.1f}% "
               f"(RMS of the pixels' standard errors / mean), {data['seconds']:.2f} s" if noise else
               f"point light, {data['seconds']:.2f} s")
    n = data["radiance"].shape[0]
    return {"data": [{"type": "image", "source": f"data:image/png;base64,{encoded}",
                      "x0": -1.0 + 1.0 / n, "dx": 2.0 / n, "y0": 1.0 - 1.0 / n, "dy": -2.0 / n,
                      "hoverinfo": "skip"}],
            "layout": {"title": {"text": f"{title}<br><sub>{caption}</sub>"},
                       "xaxis": {"visible": False, "scaleanchor": "y"},
                       "yaxis": {"visible": False, "autorange": "reversed"},
                       "margin": {"l": 10, "r": 10, "t": 60, "b": 10}}}
