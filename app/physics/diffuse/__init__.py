"""The diffuse registry: one module per model, each registering its class with
``@DIFFUSES.register``; every module of this package is imported here, so adding a
diffuse model is adding its file. The BRDF weights the chosen model by ``kd`` (ρ).
"""
from __future__ import annotations

from ..registry import import_modules
from .base import DIFFUSES, Diffuse

import_modules(__name__, __path__, skip=("base",))

__all__ = ["DIFFUSES", "Diffuse"]
