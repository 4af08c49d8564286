"""The model registry (``model=<name>``): every family, found, not listed. A family is a
package with a ``family.py`` that defines ``FAMILY`` (app/model/family.py): the packages
of app/ (microfacet here, principled in app/principled/), then those in each directory
of the setting BRDF_MODEL_DIRS (a family added without editing the application).

:func:`make_spec` validates flat parameters into a :class:`ModelSpec` through the chosen
family; nothing outside a family's own package tests which family a model is.
"""
from __future__ import annotations

import importlib
import importlib.util
import os
import sys
from dataclasses import dataclass, field
from functools import lru_cache
from pathlib import Path
from typing import Literal, Optional

from pydantic import Field
from pydantic.fields import FieldInfo

from ..config import environment
from ..errors import ParameterError
from .family import Family

#: The family of a query that names none (the first the API ever had).
DEFAULT = "microfacet"
#: The module a family package defines its entry in.
ENTRY = "family"


def _app_families() -> list[Family]:
    """FAMILY of every package of app/ (and of app/model itself) that has a family.py."""
    root = Path(__file__).resolve().parents[1]
    out = [importlib.import_module(".microfacet", __package__).FAMILY]
    for path in sorted(root.glob(f"*/{ENTRY}.py")):
        if path.parent.name != "model":
            out.append(importlib.import_module(f"app.{path.parent.name}.{ENTRY}").FAMILY)
    return out


def _plugin_families(dirs: str) -> list[Family]:
    """FAMILY of every package (a directory with __init__.py and family.py) in the
    directories ``dirs`` (os.pathsep-separated), imported as ``brdf_model_<package>``."""
    out = []
    for d in filter(None, dirs.split(os.pathsep)):
        for init in sorted(Path(d).glob(f"*/__init__.py")):
            package = init.parent
            if not (package / f"{ENTRY}.py").exists():
                continue
            name = f"brdf_model_{package.name}"
            if name not in sys.modules:
                spec = importlib.util.spec_from_file_location(name, init,
                                                              submodule_search_locations=[str(package)])
                module = importlib.util.module_from_spec(spec)
                sys.modules[name] = module
                spec.loader.exec_module(module)
            out.append(importlib.import_module(f"{name}.{ENTRY}").FAMILY)
    return out


@lru_cache(maxsize=1)
def families() -> dict[str, Family]:
    """name → family, in menu order (found once per process)."""
    out: dict[str, Family] = {}
    for family in _app_families() + _plugin_families(environment().model_dirs):
        if family.name in out:
            raise ValueError(f"two model families are named {family.name!r}")
        out[family.name] = family
    return out


def family_of(values: dict) -> Family:
    return families()[values.get("model", DEFAULT)]


@dataclass(frozen=True)
class ModelSpec:
    """The validated, flat description of a model: what URLs and API calls carry. Build
    one with :func:`make_spec`; derive others with the typed edits ``with_`` and
    ``at_alpha`` (validated again) instead of editing ``values``."""
    values: dict
    _built: list = field(default_factory=list, compare=False, repr=False)

    @property
    def family(self) -> Family:
        return family_of(self.values)

    def key(self) -> tuple:
        """A hashable identity of the model (cache keys)."""
        return tuple(sorted(self.values.items()))

    def as_query(self) -> dict:
        """The model as make_spec (and every endpoint) takes it: only what applies, no
        derived values (the family's own spelling)."""
        return self.family.as_query(self.values)

    def with_(self, **changes) -> "ModelSpec":
        """This model with ``changes`` (``None`` removes a value), validated again. A
        change of a name the family does not take is refused naming ``model``."""
        family = self.family
        foreign = sorted(set(changes) - set(family.own_names()))
        if foreign:
            takers = [f.name for f in families().values() if set(foreign) <= set(f.own_names())]
            raise ParameterError("model", f"this analysis changes {', '.join(foreign)}, which "
                                          f"model={family.name} does not take; it applies to "
                                          f"model={' or model='.join(takers) or DEFAULT} only")
        query = self.as_query()
        query = family.edit(query, changes) if family.edit else {**query, **changes}
        return make_spec(**query)

    def at_alpha(self, alpha: float) -> "ModelSpec":
        """The isotropic model with roughness ``alpha`` (a second lobe's α₂ is kept)."""
        return self.with_(alpha=float(alpha), alpha_y=None)

    def brdf(self):
        """The BRDF, built once per spec."""
        if not self._built:
            self._built.append(self.family.brdf(self.values))
        return self._built[0]


def make_spec(**given) -> ModelSpec:
    """Validate flat parameters through the family ``model`` names (default microfacet):
    a name only another family takes is refused naming it; ``None`` means not given."""
    given = {k: x for k, x in given.items() if x is not None}
    name = given.pop("model", DEFAULT)
    found = families()
    if name not in found:
        raise ParameterError("model", f"model must be one of {', '.join(found)}; got {name!r}")
    family = found[name]
    own = set(family.own_names())
    for other in given:
        if other not in own:
            takers = [f.name for f in found.values() if other in f.own_names()]
            if takers:
                raise ParameterError(other, f"{other} applies only with model={' or model='.join(takers)}")
    spec = ModelSpec(family.make_values(given))
    try:
        brdf = spec.brdf()
    except ParameterError:
        raise
    except ValueError as exc:  # a model that cannot be built, e.g. an anisotropic GTR,
        # or whose compensation table would not build within the request's time budget
        raise ParameterError(getattr(exc, "param", "alpha_y"), str(exc)) from exc
    # Derived quantities for display (Blinn-Phong's α_p); not parameters.
    spec.values.update(getattr(getattr(brdf, "ndf", None), "derived", dict)())
    return spec


def refuse_view(view: str, values: dict) -> None:
    """ParameterError naming ``model`` when the model's family is not drawn by ``view``."""
    family = family_of(values)
    why = family.views(view)
    if why is not None:
        raise ParameterError("model", f"the {view} view does not apply to model={family.name}: {why}")


def refuse_method(method: str, values: dict) -> None:
    """ParameterError naming ``method`` when that albedo method does not apply."""
    family = family_of(values)
    if method not in family.albedo_methods:
        raise ParameterError("method", f"method={method} does not apply to model={family.name}; "
                                       f"it takes method={', '.join(family.albedo_methods)}")


def _bounds(info: FieldInfo) -> tuple[Optional[float], Optional[float]]:
    lo = next((m.ge for m in info.metadata if hasattr(m, "ge")), None)
    hi = next((m.le for m in info.metadata if hasattr(m, "le")), None)
    return lo, hi


def _widened(first: tuple, second: tuple) -> tuple:
    """One field for a name two families take: the union of their ranges (each family
    refuses the rest with its own range, make_values)."""
    (annotation, a), (_, b) = first, second
    (lo_a, hi_a), (lo_b, hi_b) = _bounds(a), _bounds(b)
    if None in (lo_a, hi_a, lo_b, hi_b):
        return first
    return (Optional[float], Field(None, ge=min(lo_a, lo_b), le=max(hi_a, hi_b),
                                   description=a.description, examples=a.examples))


def query_fields() -> dict:
    """Every family's query fields (a name several take spans their ranges) and ``model``."""
    found = families()
    fields: dict = {"model": (Literal[tuple(found)], Field(
        DEFAULT, description="the model family: " + "; ".join(f"{f.name} ({f.label})"
                                                                for f in found.values())))}
    for family in found.values():
        for name, spec in family.query_fields().items():
            fields[name] = _widened(fields[name], spec) if name in fields else spec
    return fields
