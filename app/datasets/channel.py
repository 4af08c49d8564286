"""The model in the data's channel: a model with an RGB material (``material=gold``) is
evaluated per channel, so the red channel of the data meets the red channel of the
model, not its luminance (issue 34)."""
from __future__ import annotations

import numpy as np

from ..materials import MaterialFresnel, evaluate_rgb

RGB = ("r", "g", "b")


def model_f(brdf, l: np.ndarray, v: np.ndarray, channel: str | None) -> np.ndarray:
    """f(l, v) of ``brdf`` in ``channel``: r, g or b of a coloured model's per-channel f;
    luminance (or none named) its luminance of the per-channel f; f itself for a model
    without colour (the same in every channel)."""
    if not isinstance(getattr(brdf, "fresnel", None), MaterialFresnel):
        return brdf.f(l, v)
    out = evaluate_rgb(brdf, l, v, ("f",))
    return out["f_rgb"][..., RGB.index(channel)] if channel in RGB else out["f"]
