"""What a model family is (``model=<name>``): one entry of the model registry, owning its
parameters, its query form, its validation, its BRDF, the views it applies to and the
albedo methods that apply to it. A family is declared in one package (``FAMILY`` in its
``family.py``); app/model/registry.py finds it — nothing else names it.
"""
from __future__ import annotations

from dataclasses import dataclass, field
from typing import Callable, Mapping, Optional

from pydantic import Field

from ..errors import ParameterError
from ..physics.params import Param
from ..physics.registry import generation

#: id(family) → (family, registries' generation, its own query names): own_names' memory
_OWN_NAMES: dict[int, tuple] = {}


def every_view_but(refused: Mapping[str, str]) -> Callable[[str], Optional[str]]:
    """A family drawn by every view except ``refused`` (view → why not)."""
    return lambda view: refused.get(view)


def only_views(views, why: str) -> Callable[[str], Optional[str]]:
    """A family drawn by ``views`` only; the others say ``why``."""
    allowed = frozenset(views)
    return lambda view: None if view in allowed else why


def param_fields(params, family: str) -> dict:
    """Query fields of continuous parameters: optional (absent = the default), bounded by
    the declared range (a family shares a name with another: the registry widens it)."""
    return {p.name: (Optional[float], Field(None, ge=p.lo, le=p.hi, examples=[p.default],
                                            description=f"model={family}: {p.description} "
                                                        f"Default {p.default:g}."))
            for p in params}


def check_range(p: Param, x) -> float:
    """``x`` as a float in p's range, else ParameterError naming p and its range (→ 422)."""
    try:
        ok = p.contains(float(x))
    except (TypeError, ValueError):
        ok = False
    if not ok:
        raise ParameterError(p.name, f"{p.name} must be a number in {p.range_text()}; got {x!r}")
    return float(x)


@dataclass(frozen=True)
class Family:
    """``make_values(given)``: validated values (``model`` among them) from the flat
    parameters given (no None, no ``model``); raises ParameterError naming the parameter.
    ``brdf(values)``: the BRDF. ``as_query(values)``: the flat parameters that give the
    same values back. ``query_fields()``: pydantic fields (annotation, FieldInfo) of the
    family's own names, what every view's query takes. ``catalogue()``: what
    ``GET /api/v1/models`` lists for it (params, options: the page's controls).
    ``views(name)``: None if the family is drawn by view ``name``, else why not.
    ``albedo_methods``: the integrate/ methods that apply (others are refused, 422).
    ``lobe_albedo(spec, mu)``: E(μ) per lobe (the principled_albedo view), if it has lobes.
    ``edit(query, changes)``: the query of the model with ``changes`` (ModelSpec.with_).
    ``title(values)``, ``differences(values)``: the figure title and the (name, value)
    pairs a file name shows (app/figures/titles.py writes the default family's, and a
    generic form for others without them). ``display_names(values)``: names a title
    shows that the figures cannot know (a measured material's), value name → text."""
    name: str
    label: str
    description: str
    reference: str
    make_values: Callable[[dict], dict]
    brdf: Callable[[dict], object]
    as_query: Callable[[dict], dict]
    query_fields: Callable[[], dict]
    catalogue: Callable[[], dict]
    views: Callable[[str], Optional[str]] = every_view_but({})
    albedo_methods: tuple[str, ...] = ()
    lobe_albedo: Optional[Callable] = None
    edit: Optional[Callable[[dict, dict], dict]] = None
    title: Optional[Callable[[dict], str]] = None
    differences: Optional[Callable[[dict], list]] = None
    display_names: Callable[[dict], dict] = lambda values: {}
    #: names this family takes besides ``model`` (filled from query_fields when empty)
    names: tuple[str, ...] = field(default=())

    def own_names(self) -> tuple[str, ...]:
        """The query names this family takes (``model`` aside). Derived from its query
        fields, whose pydantic Fields cost ~1 ms to build — two thirds of every make_spec
        — so kept until a registry changes."""
        if self.names:
            return self.names
        kept = _OWN_NAMES.get(id(self))
        if kept is None or kept[0] is not self or kept[1] != generation():
            kept = (self, generation(), tuple(n for n in self.query_fields() if n != "model"))
            _OWN_NAMES[id(self)] = kept
        return kept[2]
