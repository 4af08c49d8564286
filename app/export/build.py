"""One export request → the numbers and the figure, for any view: the views' own pipeline
(:func:`app.views.run`, or :func:`app.views.compare` when the request varies a
parameter) plus what an export adds: the image size and the CSV's comment lines.
Shared by the API's export routes and the CLI, so both produce the same bytes."""
from __future__ import annotations

from dataclasses import dataclass, field

import plotly.io as pio
from pydantic import BaseModel, Field, create_model

from .. import figures
from ..config import Settings
from ..errors import ParameterError
from ..model import ModelSpec
from ..views import View, compare, run, vary
from . import table

# Image size bounds (CSS pixels) and scale; Settings.max_export_pixels bounds the product.
SIZE_MIN, SIZE_MAX = 100, 4096
SCALE_MIN, SCALE_MAX = 0.25, 8.0
DEFAULT_WIDTH, DEFAULT_HEIGHT = 800, 560

# Query fields that only steer the export, never the computation.
EXPORT_FIELDS = ("vary", "values", "width", "height", "scale")

_images: dict[str, type] = {}


def export_query(view: View) -> type[BaseModel]:
    """The view's figure query plus ``vary`` and ``values`` (CSV, figure JSON)."""
    return vary.figure_query(view)


def image_query(view: View) -> type[BaseModel]:
    """:func:`export_query` plus the image size (SVG, PNG)."""
    if view.name not in _images:
        _images[view.name] = create_model(
            f"{view.figure_query.__name__}Image", __base__=export_query(view),
            width=(int, Field(DEFAULT_WIDTH, ge=SIZE_MIN, le=SIZE_MAX,
                              description="image width in CSS pixels", examples=[1200])),
            height=(int, Field(DEFAULT_HEIGHT, ge=SIZE_MIN, le=SIZE_MAX,
                               description="image height in CSS pixels", examples=[800])),
            scale=(float, Field(1.0, ge=SCALE_MIN, le=SCALE_MAX,
                                description="PNG pixels per CSS pixel (2 for a sharp slide)",
                                examples=[2.0])))
    return _images[view.name]


def check_image_size(q, settings: Settings) -> None:
    pixels = q.width * q.height * q.scale ** 2
    if pixels > settings.max_export_pixels:
        raise ParameterError("scale", f"width×height×scale² = {pixels:.0f} pixels exceeds the limit "
                                      f"{settings.max_export_pixels} (setting BRDF_MAX_EXPORT_PIXELS)")


@dataclass
class Produced:
    view: View
    figure: dict
    payloads: list[tuple[object, dict]]      # (value of `vary`, or None; data)
    specs: list[ModelSpec]
    queries: list[BaseModel]
    vary: str | None = None
    meta: dict = field(default_factory=dict)

    def csv(self) -> str:
        if self.vary is None:
            return table.to_csv(self.payloads[0][1], self.meta)
        return table.to_csv_variants(self.vary, self.payloads, self.meta)

    @property
    def data(self) -> dict:
        """The data endpoint's payload (a single state only)."""
        return self.payloads[0][1]


def _state(view: View, q) -> dict:
    """What the request asked for, for a CSV's comment lines."""
    out = {"view": view.name}
    for name in view.figure_query.model_fields:
        value = getattr(q, name)
        if value is not None and not isinstance(value, list):
            out[name] = value
    return out


def produce(view: View, q, settings: Settings) -> Produced:
    """Compute and draw one export request (``q`` an :func:`export_query` instance, or
    the plain figure query)."""
    base = vary.base(view, q)
    expanded = vary.expand(view, q)
    if expanded is None:
        result = run(view, base, settings)
        meta = {**_state(view, base), **{k: v for k, v in result.spec.values.items() if v is not None}}
        return Produced(view, result.figure(), [(None, result.data)], [result.spec], [base], meta=meta)
    queries, labels, caption = expanded
    comparison = compare(view, queries, labels, caption, settings, param="vary")
    meta = {**_state(view, base), "vary": q.vary}
    meta.pop(q.vary, None)
    return Produced(view, comparison.figure,
                    [(value, r.data) for value, r in zip(q.values, comparison.results)],
                    [r.spec for r in comparison.results], queries, vary=q.vary, meta=meta)


def figure_json(produced: Produced) -> str:
    return figures.to_json(produced.figure)


def standalone_html(produced: Produced, plotlyjs: str | bool = True) -> str:
    """A self-contained HTML page with the figure (plotly.js inlined by default, so it
    opens offline, e.g. from a USB stick in a lecture hall)."""
    return pio.to_html(produced.figure, include_plotlyjs=plotlyjs, full_html=True,
                       config={"displaylogo": False, "responsive": True}, validate=False)
