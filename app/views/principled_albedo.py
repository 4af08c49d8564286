"""How much each lobe of the principled BRDF reflects: E(θ_v) per lobe and channel,
stacked (app/principled/albedo.py)."""
from __future__ import annotations

from typing import Annotated

import numpy as np
from pydantic import Field

from ..integrate.methods import albedo_by
from ..principled.figure import stacked_albedo_figure
from . import schemas
from .view import View


class PrincipledAlbedoQuery(schemas.ModelQuery):
    n: Annotated[int, Field(ge=2, le=91, description="view angles θ_v = 0..90°, both ends")] = 19


def compute(spec, q) -> dict:
    """The principled lobes; for a microfacet model its two: the diffuse term and the
    specular lobe (with its Kulla-Conty part), sheen and clearcoat 0."""
    mu = np.cos(np.radians(np.linspace(0.0, 90.0, q.n)))
    if spec.values.get("model") == "principled":
        return spec.brdf().albedo_by(mu)
    specular = albedo_by(spec.with_(kd=0.0).brdf(), mu, average=False)
    E_d, E_d_error = spec.brdf().diffuse_albedo(mu)
    zero = {"E": np.zeros_like(mu), "E_error": 0.0, "E_avg": 0.0}
    lobes = {"diffuse": {"E": E_d, "E_error": E_d_error, "E_avg": spec.brdf().diffuse_albedo_avg()[0]},
             "specular": {"E": specular["E"], "E_error": float(np.max(specular["E_error"])),
                          "E_avg": float(albedo_by(spec.with_(kd=0.0).brdf(), [1.0])["E_avg"])},
             "sheen": zero, "clearcoat": zero}
    return {"mu": mu, "E": E_d + specular["E"], "lobes": lobes, "channel": "luminance"}


VIEW = View(
    "principled_albedo", "Principled albedo by lobe",
    "E(θ_v) of each lobe (diffuse, sheen, specular, clearcoat), stacked to the total: how much "
    "each reflects.",
    PrincipledAlbedoQuery, PrincipledAlbedoQuery, compute,
    lambda data, spec, q: stacked_albedo_figure(data, "Principled BRDF: albedo by lobe"))
