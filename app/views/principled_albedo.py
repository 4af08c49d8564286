"""How much each lobe of the model reflects: E(θ_v) per lobe and channel, stacked (each
family's ``lobe_albedo``; families without lobes are not drawn by this view)."""
from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import Field

from ..figures.lobe_albedo import stacked_albedo_figure
from ..figures.style import model_title
from . import schemas
from .view import View


class PrincipledAlbedoQuery(schemas.ModelQuery):
    n: Annotated[int, Field(ge=2, le=91, description="view angles θ_v = 0..90°, both ends")] = 19


def compute(spec, q) -> dict:
    """Each lobe's E(θ_v), as the model's family computes it (its ``lobe_albedo``: the
    principled lobes; the microfacet model's diffuse term and specular lobe)."""
    mu = np.cos(np.radians(np.linspace(0.0, 90.0, q.n)))
    return spec.family.lobe_albedo(spec, mu)


VIEW = View(
    "principled_albedo", "Principled albedo by lobe",
    "E(θ_v) of each lobe (diffuse, sheen, specular, clearcoat), stacked to the total: how much "
    "each reflects.",
    PrincipledAlbedoQuery, PrincipledAlbedoQuery, compute,
    lambda data, spec, q: stacked_albedo_figure(data, f"Albedo by lobe — {model_title(spec.values)}"),
    overlayable=True)
