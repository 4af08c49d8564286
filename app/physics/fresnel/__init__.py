"""The Fresnel registry: one module per model, each registering its class with
``@FRESNELS.register``; every module of this package is imported here, so adding a
Fresnel model is adding its file.
"""
from __future__ import annotations

from ..registry import import_modules
from .base import FRESNELS, Fresnel
from .conductor import Conductor, conductor_reflectance
from .dielectric import Dielectric, dielectric_reflectance, f0_from_ior, ior_from_f0
from .none import NoFresnel
from .schlick import Schlick

import_modules(__name__, __path__, skip=("base",))

__all__ = ["FRESNELS", "Conductor", "Dielectric", "Fresnel", "NoFresnel", "Schlick",
           "conductor_reflectance", "dielectric_reflectance", "f0_from_ior", "ior_from_f0"]
