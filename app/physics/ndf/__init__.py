"""The NDF registry.

Every module in this package that defines an NDF subclass decorated with ``@register``
is imported here, so adding an NDF is adding one file: it then appears in
``/api/v1/models``, the API's ``ndf`` parameter and the page's menu.
"""
from __future__ import annotations

import importlib
import pkgutil

from .base import ALPHA, ALPHA_Y, NDF, ShapeInvariantNDF, SlopeSpaceNDF

NDFS: dict[str, type[NDF]] = {}


def register(cls: type[NDF]) -> type[NDF]:
    if cls.name in NDFS:
        raise ValueError(f"NDF {cls.name!r} registered twice")
    NDFS[cls.name] = cls
    return cls


def make_ndf(name: str, alpha: float, alpha_y: float | None = None, **shape) -> NDF:
    return NDFS[name](alpha, alpha_y, **shape)


def _import_all() -> None:
    for info in sorted(pkgutil.iter_modules(__path__), key=lambda i: i.name):
        if info.name != "base":
            importlib.import_module(f"{__name__}.{info.name}")


_import_all()
NDFS = dict(sorted(NDFS.items(), key=lambda kv: (kv[1].menu_order, kv[0])))

__all__ = ["ALPHA", "ALPHA_Y", "NDF", "NDFS", "ShapeInvariantNDF", "SlopeSpaceNDF", "make_ndf",
           "register"]
