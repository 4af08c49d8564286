"""The one pipeline every caller uses (routes, exports, the gallery, the CLI):
check → model → compute → figure, for one query (:func:`run`) or several drawn as one
(:func:`compare`: the POST ``models[]`` of the API and ``vary``/``values`` alike)."""
from __future__ import annotations

from dataclasses import dataclass

from ..config import Settings
from ..errors import ParameterError
from ..figures.markup import markup
from ..figures.overlay import overlay, overlayable, shared_description
from ..figures.style import model_title
from ..integrate.methods import METHODS
from ..model import OPTIONS, ModelSpec, refuse_method, refuse_view
from . import schemas
from .view import View


@dataclass
class Result:
    """One query of one view: its model and the arrays; ``figure()`` draws them."""
    view: View
    query: object
    spec: ModelSpec
    data: dict

    def figure(self) -> dict:
        # indexed symbols as Plotly subscripts whoever built the figure (figures/markup.py)
        return markup(self.view.figure(self.data, self.spec, self.query))


@dataclass
class Comparison:
    """Several queries of one view overlaid: one curve (or set) per label."""
    results: list[Result]
    labels: list[str]
    figure: dict


def run(view: View, query, settings: Settings) -> Result:
    """Refuse the query before any work (what the model's family does not take: the view
    itself, an albedo method; then view.check), build the model, compute."""
    refuse(view, query)
    view.check(query, settings)
    spec = schemas.spec_of(query)
    return Result(view, query, spec, view.compute(spec, query))


def refuse(view: View, query) -> None:
    """ParameterError (422) naming ``model`` when the family of the query's model is not
    drawn by ``view``, naming ``method`` when the albedo method asked does not apply to it
    (the family's declared capabilities, app/model/family.py)."""
    values = schemas.model_values(query)
    refuse_view(view.name, values)
    method = getattr(query, "method", None)
    if method in METHODS:
        refuse_method(method, values)


def compare(view: View, queries: list, labels: list[str] | None, caption: str | None,
            settings: Settings, param: str = "vary", where: list[str] | None = None) -> Comparison:
    """:func:`run` each query and overlay their figures, one legend label per query
    (None: what differs between the models), titled "<the view's figure title> —
    <caption>" (None: the labels compared). A figure that is not a curve is refused
    naming ``param``; an error of query k is prefixed by ``where[k]`` when given."""
    if len(queries) > 1:
        _refuse_unoverlayable(view, queries[0], settings, param)
    results = []
    for k, query in enumerate(queries):
        try:
            results.append(run(view, query, settings))
        except ParameterError as exc:
            if where is None:
                raise
            raise ParameterError(f"{where[k]}.{exc.param}", f"{where[k]}: {exc.message}",
                                 exc.status, exc.loc) from None
    labels = labels or difference_labels([r.spec.values for r in results])
    figures = [r.figure() for r in results]
    # "D(θ_m) — GGX · F Gold; alpha = 0.1, 0.4": what every curve shares, then what varies
    shared = shared_description(figures)
    title = None if caption is None else \
        f"{_title_text(figures[0]).split(' — ')[0]} — {shared + '; ' if shared else ''}{caption}"
    return Comparison(results, labels, overlay(figures, labels, title, param))


#: grid and curve sizes of the probe that tells, in milliseconds, whether a view's figures
#: can be overlaid at all (a 3-D surface cannot): eight 500×500 lobes took 34 s to compute
#: before that answer
PROBE_SIZE = 5


def _refuse_unoverlayable(view: View, query, settings: Settings, param: str) -> None:
    small = {k: PROBE_SIZE for k in ("n", "n_theta", "n_phi") if k in type(query).model_fields}
    try:
        probe = run(view, query.model_copy(update=small), settings).figure()
    except ParameterError:
        return          # the query's own error is reported by the loop, with its place
    if not overlayable(probe):
        overlay([probe, probe], ["", ""], None, param)    # raises, with overlay's reason


def difference_labels(specs: list[dict]) -> list[str]:
    """Legend labels naming what differs between the models (all of the title if nothing
    does): "ndf=ggx, alpha=0.2" / "ndf=beckmann, alpha=0.2" → "ggx" / "beckmann"."""
    keys = [k for k in dict.fromkeys(k for s in specs for k in s)
            if len({repr(s.get(k)) for s in specs}) > 1]
    if not keys:
        return [model_title(s) for s in specs]

    def show(k, value):
        if k in OPTIONS:
            return str(value)
        return f"{k}={value:g}" if isinstance(value, float) else f"{k}={value}"
    return [", ".join(show(k, s.get(k)) for k in keys if s.get(k) is not None) or "default"
            for s in specs]


def _title_text(figure: dict) -> str:
    title = figure.get("layout", {}).get("title")
    return title.get("text", "") if isinstance(title, dict) else str(title or "")
