"""Arrays → Plotly figure dicts. No physics here: builders take what ``quantities``
computed. ``to_json`` encodes numpy arrays as Plotly typed arrays (compact, exact)."""
from __future__ import annotations

import plotly.io as pio

from .curves import albedo_figure, g1_figure, ndf_figure
from .fresnel import fresnel_figure
from .images import lit_sphere_figure, slice_figure
from .lobes import lobe3d_figure, lobe_figure
from .maps import g2_figure


def to_json(figure: dict) -> str:
    return pio.to_json(figure, validate=False, remove_uids=False)


__all__ = ["albedo_figure", "fresnel_figure", "g1_figure", "g2_figure", "lobe3d_figure",
           "lobe_figure", "ndf_figure", "to_json",
           "lit_sphere_figure", "slice_figure"]
