"""GET /api/v1/principled: the principled BRDF's parameters, ranges, defaults and options
(what the page builds its controls from). Its views — principled_albedo, sphere_env — are
views like any other (app/views/)."""
from __future__ import annotations

from fastapi import APIRouter

from ..principled.params import BASE_COLOR_DEFAULT, OPTIONS, PARAMS
from ..principled.spec import ROUGHNESS
from .http.query_route import QueryModelRoute

router = APIRouter(prefix="/api/v1", route_class=QueryModelRoute)


@router.get("/principled", tags=["meta"], summary="The principled BRDF's parameters and options",
            responses={200: {"content": {"application/json": {"example": {
                "base_color": {"default": [0.82, 0.67, 0.16], "lo": 0.0, "hi": 1.0},
                "params": [{"name": "metallic", "lo": 0.0, "hi": 1.0, "default": 0.0}],
                "options": {"lobe": {"label": "Lobe shown", "default": "all", "choices": []}},
                "reference": "Burley 2012"}}}}})
def principled_catalogue():
    return {"base_color": {"default": list(BASE_COLOR_DEFAULT), "lo": 0.0, "hi": 1.0},
            "params": [ROUGHNESS.as_dict()] + [p.as_dict() for p in PARAMS],
            "options": {name: {"label": label, "default": default,
                               "choices": [{"name": c.name, "label": c.label, "description": c.description}
                                           for c in choices.values()]}
                        for name, (label, choices, default) in OPTIONS.items()},
            "reference": "Burley 2012, Physically-Based Shading at Disney; docs/principled.md"}
