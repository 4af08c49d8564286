"""One export request → the numbers and the figure, for any view in VIEWS.

Shared by the API's export routes and the CLI, so both produce the same bytes. An
export may vary one parameter over a few values (``vary=alpha&values=0.1,0.3,0.6``):
each value is validated exactly as a request with that value would be, computed, and
the figures are overlaid (:mod:`app.figures.overlay`).
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Annotated, Literal, Optional

from pydantic import BaseModel, BeforeValidator, Field, ValidationError, create_model

from .. import figures
from ..api import schemas
from ..errors import ParameterError
from ..api.views import VIEWS, View
from ..config import Settings
from ..figures.overlay import overlay
from ..figures.style import PALETTE
from ..model import ModelSpec, make_spec
from . import table

# At most one curve per palette colour.
MAX_VARIANTS = len(PALETTE)
# Image size bounds (CSS pixels) and scale; Settings.max_export_pixels bounds the product.
SIZE_MIN, SIZE_MAX = 100, 4096
SCALE_MIN, SCALE_MAX = 0.25, 8.0
DEFAULT_WIDTH, DEFAULT_HEIGHT = 800, 560

# Query fields that only steer the export, never the computation.
EXPORT_FIELDS = ("vary", "values", "width", "height", "scale")


def _strings(value):
    if isinstance(value, str):
        value = [value]
    if isinstance(value, (list, tuple)):
        out = []
        for item in value:
            parts = [p.strip() for p in str(item).split(",")]
            if any(p == "" for p in parts):
                raise ValueError("empty list element (values are comma-separated)")
            out.extend(parts)
        return out
    return value


ValueList = Annotated[list[str], BeforeValidator(_strings), Field(
    description=f"the values of `vary`, comma-separated, at most {MAX_VARIANTS}",
    examples=["ggx,beckmann"])]


def view_fields(view: View) -> list[str]:
    """The figure query's fields that are not model parameters (geometry, flags)."""
    return [n for n in view.figure_query.model_fields if n not in schemas.ModelQuery.model_fields]


# Fields that set resolution or accuracy, not what is drawn: never worth a curve each.
NOT_VARIED = ("n", "n_theta", "n_phi", "mu", "tol")


def vary_choices(view: View) -> tuple[str, ...]:
    """The parameters an export of this view may vary."""
    return tuple(n for n in view.figure_query.model_fields if n not in NOT_VARIED)


_models: dict[tuple[str, str], type] = {}


def export_query(view: View) -> type[BaseModel]:
    """The view's figure query plus ``vary`` and ``values`` (CSV, figure JSON)."""
    key = (view.name, "export")
    if key not in _models:
        _models[key] = create_model(
            f"{view.figure_query.__name__}Export", __base__=view.figure_query,
            vary=(Optional[Literal[vary_choices(view)]], Field(
                None, description="a parameter to vary: one curve per value of `values` "
                                  "(curve figures only)", examples=["ndf"])),
            values=(Optional[ValueList], None))
    return _models[key]


def image_query(view: View) -> type[BaseModel]:
    """:func:`export_query` plus the image size (SVG, PNG)."""
    key = (view.name, "image")
    if key not in _models:
        _models[key] = create_model(
            f"{view.figure_query.__name__}Image", __base__=export_query(view),
            width=(int, Field(DEFAULT_WIDTH, ge=SIZE_MIN, le=SIZE_MAX,
                              description="image width in CSS pixels", examples=[1200])),
            height=(int, Field(DEFAULT_HEIGHT, ge=SIZE_MIN, le=SIZE_MAX,
                               description="image height in CSS pixels", examples=[800])),
            scale=(float, Field(1.0, ge=SCALE_MIN, le=SCALE_MAX,
                                description="PNG pixels per CSS pixel (2 for a sharp slide)",
                                examples=[2.0])))
    return _models[key]


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


def _one(view: View, q, settings: Settings):
    view.check(q, settings)
    spec = make_spec(**schemas.model_values(q))
    data = view.compute(spec, q)
    return spec, data, view.figure(data, spec, q)


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
    vary, values = getattr(q, "vary", None), getattr(q, "values", None)
    if vary is None and values:
        raise ParameterError("vary", "values is given but vary is not: name the parameter to vary")
    base = view.figure_query.model_validate(
        {k: getattr(q, k) for k in view.figure_query.model_fields if k in q.model_fields_set})
    if vary is None:
        spec, data, fig = _one(view, base, settings)
        meta = {**_state(view, base), **{k: v for k, v in spec.values.items() if v is not None}}
        return Produced(view, fig, [(None, data)], [spec], [base], meta=meta)
    if not values:
        raise ParameterError("values", f"vary={vary} needs values: a comma-separated list")
    if len(values) > MAX_VARIANTS:
        raise ParameterError("values", f"{len(values)} values; at most {MAX_VARIANTS} (one per colour)")
    if len(set(values)) != len(values):
        raise ParameterError("values", "values has a repeated value")
    given = {k: getattr(q, k) for k in view.figure_query.model_fields if k in q.model_fields_set}
    payloads, figs, specs, queries = [], [], [], []
    for value in values:
        try:
            qk = view.figure_query.model_validate({**given, vary: value})
        except ValidationError as e:
            msg = e.errors()[0].get("msg", "invalid")
            raise ParameterError("values", f"{vary}={value}: {msg}") from None
        spec, data, fig = _one(view, qk, settings)
        payloads.append((value, data))
        figs.append(fig)
        specs.append(spec)
        queries.append(qk)
    head = _title_text(figs[0]).split(" — ")[0]
    fig = overlay(figs, [f"{vary}={v}" for v in values], f"{head} — {vary} = {', '.join(values)}")
    meta = {**_state(view, base), "vary": vary}
    meta.pop(vary, None)
    return Produced(view, fig, payloads, specs, queries, vary=vary, meta=meta)


def _title_text(fig: dict) -> str:
    title = fig.get("layout", {}).get("title")
    return title.get("text", "") if isinstance(title, dict) else str(title or "")


def figure_json(produced: Produced) -> str:
    return figures.to_json(produced.figure)


def standalone_html(produced: Produced, plotlyjs: str | bool = True) -> str:
    """A self-contained HTML page with the figure (plotly.js inlined by default, so it
    opens offline, e.g. from a USB stick in a lecture hall)."""
    import plotly.io as pio
    return pio.to_html(produced.figure, include_plotlyjs=plotlyjs, full_html=True,
                       config={"displaylogo": False, "responsive": True}, validate=False)


def lookup(kind: str) -> View:
    if kind not in VIEWS:
        raise ParameterError("kind", f"unknown figure kind {kind!r}; one of {', '.join(VIEWS)}",
                         status=404, loc="path")
    return VIEWS[kind]
