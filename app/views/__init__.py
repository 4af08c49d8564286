"""The views: what each computes and draws (one module per view), and the one pipeline
that runs them (:func:`run`, :func:`compare`). Every caller — routes, exports, gallery,
CLI — goes through here; nothing here knows HTTP."""
from __future__ import annotations

from ..errors import ParameterError
from . import advise, albedo, checks, fresnel, g1, g2, lobe, lobe3d, ndf, samples, sphere, tradeoff
from . import principled_albedo, sphere_env
from . import slice as half_difference
from .pipeline import Comparison, Result, compare, run
from .view import ROLES, View

#: Every view, in the order the page lists them.
VIEWS: dict[str, View] = {v.name: v for v in (
    ndf.VIEW, g1.VIEW, lobe.VIEW, lobe3d.VIEW, albedo.VIEW, g2.VIEW, fresnel.VIEW,
    sphere.VIEW, half_difference.VIEW, advise.VIEW, checks.VIEW, samples.VIEW, tradeoff.VIEW,
    sphere_env.VIEW, principled_albedo.VIEW)}


def lookup(name: str) -> View:
    """The view called ``name``; unknown: a 404 that lists the views there are."""
    if name not in VIEWS:
        raise ParameterError("view", f"unknown view {name!r}; one of {', '.join(VIEWS)}",
                             status=404, loc="path")
    return VIEWS[name]


__all__ = ["ROLES", "VIEWS", "Comparison", "Result", "View", "compare", "lookup", "run"]
