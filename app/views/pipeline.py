"""The one pipeline every caller uses (routes, exports, the gallery, the CLI):
check → model → compute → figure, for one query (:func:`run`) or several drawn as one
(:func:`compare`: the POST ``models[]`` of the API and ``vary``/``values`` alike)."""
from __future__ import annotations

from dataclasses import dataclass

from ..config import Settings
from ..errors import ParameterError
from ..figures.overlay import overlay
from ..model import ModelSpec
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
        return self.view.figure(self.data, self.spec, self.query)


@dataclass
class Comparison:
    """Several queries of one view overlaid: one curve (or set) per label."""
    results: list[Result]
    labels: list[str]
    figure: dict


def run(view: View, query, settings: Settings) -> Result:
    """Refuse the query before any work (view.check), build the model, compute."""
    view.check(query, settings)
    spec = schemas.spec_of(query)
    return Result(view, query, spec, view.compute(spec, query))


def compare(view: View, queries: list, labels: list[str], caption: str, settings: Settings,
            param: str = "vary", where: list[str] | None = None) -> Comparison:
    """:func:`run` each query and overlay their figures, titled "<the view's figure
    title> — <caption>". A figure that is not a curve is refused naming ``param``; an
    error of query k is prefixed by ``where[k]`` when given (``models[k]``)."""
    results = []
    for k, query in enumerate(queries):
        try:
            results.append(run(view, query, settings))
        except ParameterError as exc:
            if where is None:
                raise
            raise ParameterError(f"{where[k]}.{exc.param}", f"{where[k]}: {exc.message}",
                                 exc.status, exc.loc) from None
    figures = [r.figure() for r in results]
    head = _title_text(figures[0]).split(" — ")[0]
    return Comparison(results, labels, overlay(figures, labels, f"{head} — {caption}", param))


def _title_text(figure: dict) -> str:
    title = figure.get("layout", {}).get("title")
    return title.get("text", "") if isinstance(title, dict) else str(title or "")
