"""The NDF registry: one module per NDF, each registering its class with
``@NDFS.register``. Every module of this package is imported here, so adding an NDF is
adding its file: it then appears in ``/api/v1/models``, the API's ``ndf`` parameter,
the page's menu, the compiled kernels and the tables.
"""
from __future__ import annotations

from ..registry import import_modules
from .base import ALPHA, ALPHA_Y, NDF, NDFS, ShapeInvariantNDF, SlopeSpaceNDF


def make_ndf(name: str, alpha: float, alpha_y: float | None = None, **shape) -> NDF:
    return NDFS[name](alpha, alpha_y, **shape)


import_modules(__name__, __path__, skip=("base",))

__all__ = ["ALPHA", "ALPHA_Y", "NDF", "NDFS", "ShapeInvariantNDF", "SlopeSpaceNDF", "make_ndf"]
