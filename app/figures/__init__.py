"""Arrays → Plotly figure dicts. No physics here: builders take what ``quantities``
computed. ``to_json`` encodes large numpy arrays as Plotly typed arrays (compact) and
writes indexed symbols as Plotly subscripts (``markup``: "θ_v" → "θ<sub>v</sub>"), also
in figures built outside this package."""
from __future__ import annotations

import base64

import numpy as np
import plotly.io as pio

from .advise import advise_figure
from .checks import checks_figure
from .curves import albedo_figure, g1_figure, ndf_figure
from .fresnel import fresnel_figure
from .images import lit_sphere_figure, slice_figure
from .lobes import lobe3d_figure, lobe_figure
from .maps import g2_figure
from .markup import markup, subscripts
from .samples import samples_figure
from .tradeoff import tradeoff_figure


# Trace arrays of at least this many numbers go out as Plotly typed arrays of float32
# in base64: 5.3 characters a number against 10-19 as JSON text, decoded by the browser
# without parsing, and encoded in time linear in the size (pio.to_json on lists took
# 1.1 s for the 3-D lobe at 250k points, 0.26 s as typed arrays). float32 keeps 7
# digits: figures are for display (hover shows 4); the data routes carry float64.
# Shorter arrays (a handful of guide points) stay readable lists. Measured: 3-D lobe 46 × 91 360 kB → 95 kB,
# lit sphere 845 kB → 320 kB.
TYPED_ARRAY_MIN = 64


def _typed_array(a: np.ndarray):
    """A Plotly typed-array spec {dtype, bdata[, shape]} (plotly.js ≥ 2.28; the served
    4.x reads it), the encoding plotly.py itself uses for validated figures."""
    a = np.ascontiguousarray(a, dtype="<f4")
    spec = {"dtype": "f4", "bdata": base64.b64encode(a.tobytes()).decode("ascii")}
    if a.ndim > 1:
        spec["shape"] = ", ".join(str(n) for n in a.shape)
    return spec


def _compact(value):
    if isinstance(value, np.ndarray) and value.dtype.kind in "fiu" and value.size >= TYPED_ARRAY_MIN:
        return _typed_array(value)
    return value


def to_json(figure: dict) -> str:
    figure = markup(figure)
    data = [{k: _compact(v) for k, v in trace.items()} for trace in figure.get("data", [])]
    return pio.to_json({**figure, "data": data}, validate=False, remove_uids=False)


__all__ = ["advise_figure", "albedo_figure", "checks_figure", "fresnel_figure", "g1_figure",
           "g2_figure", "lit_sphere_figure", "lobe3d_figure", "lobe_figure", "markup", "ndf_figure",
           "samples_figure", "slice_figure", "subscripts", "to_json", "tradeoff_figure"]
