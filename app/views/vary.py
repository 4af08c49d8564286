"""``vary`` + ``values``: one curve per value of one parameter, on every curve route
(the figure route and its exports alike). Each value is validated exactly as a request
with that value would be."""
from __future__ import annotations

from typing import Annotated, Literal, Optional

from pydantic import BaseModel, BeforeValidator, Field, ValidationError, create_model

from ..errors import ParameterError
from ..figures.style import PALETTE
from .view import View

#: At most one curve per palette colour.
MAX_VARIANTS = len(PALETTE)
#: Fields that set resolution or accuracy, not what is drawn: never worth a curve each.
NOT_VARIED = ("n", "n_theta", "n_phi", "mu", "tol")


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


def vary_choices(view: View) -> tuple[str, ...]:
    """The parameters a figure of this view may vary."""
    return tuple(n for n in view.figure_query.model_fields if n not in NOT_VARIED)


_queries: dict[str, type] = {}


def figure_query(view: View) -> type[BaseModel]:
    """The view's figure query plus ``vary`` and ``values``: what its figure route and
    every export take."""
    if view.name not in _queries:
        _queries[view.name] = create_model(
            f"{view.figure_query.__name__}Vary", __base__=view.figure_query,
            vary=(Optional[Literal[vary_choices(view)]], Field(
                None, description="a parameter to vary: one curve per value of `values` "
                                  "(curve figures only)", examples=["ndf"])),
            values=(Optional[ValueList], None))
    return _queries[view.name]


def base(view: View, q) -> BaseModel:
    """The plain figure query of ``q`` (vary and values left out)."""
    return view.figure_query.model_validate(
        {k: getattr(q, k) for k in view.figure_query.model_fields if k in q.model_fields_set})


def expand(view: View, q) -> tuple[list, list[str], str] | None:
    """(one query per value, their labels, the caption) of a query with ``vary``, or
    None without it."""
    vary, values = getattr(q, "vary", None), getattr(q, "values", None)
    if vary is None:
        if values:
            raise ParameterError("vary", "values is given but vary is not: name the parameter to vary")
        return None
    if not values:
        raise ParameterError("values", f"vary={vary} needs values: a comma-separated list")
    if len(values) > MAX_VARIANTS:
        raise ParameterError("values", f"{len(values)} values; at most {MAX_VARIANTS} (one per colour)")
    if len(set(values)) != len(values):
        raise ParameterError("values", "values has a repeated value")
    given = {k: getattr(q, k) for k in view.figure_query.model_fields if k in q.model_fields_set}
    queries = []
    for value in values:
        try:
            queries.append(view.figure_query.model_validate({**given, vary: value}))
        except ValidationError as e:
            raise ParameterError("values", f"{vary}={value}: {e.errors()[0].get('msg', 'invalid')}") from None
    return queries, [f"{vary}={v}" for v in values], f"{vary} = {', '.join(values)}"
