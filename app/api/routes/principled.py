"""GET /api/v1/principled: the principled family's entry of GET /api/v1/models on its own
(the address docs/principled.md and the README give), in the form it has had since it
was added: base_color, params, options, views, microfacet_only, reference."""
from __future__ import annotations

from fastapi import APIRouter

from ...model import families
from ..deps import Route
from .meta import family_entry

router = APIRouter(prefix="/api/v1", route_class=Route)

#: the family this address describes
FAMILY = "principled"


@router.get("/principled", tags=["meta"], summary="The principled BRDF's parameters and options",
            responses={200: {"content": {"application/json": {"example": {
                "base_color": {"default": [0.82, 0.67, 0.16], "lo": 0.0, "hi": 1.0},
                "params": [{"name": "metallic", "lo": 0.0, "hi": 1.0, "default": 0.0}],
                "options": {"lobe": {"label": "Lobe shown", "default": "all", "choices": []}},
                "views": ["lobe", "sphere_env"], "microfacet_only": {"checks": "why"},
                "reference": "Burley 2012"}}}}})
def principled_catalogue():
    entry = family_entry(families()[FAMILY])
    colour = entry["colors"][0]
    return {"base_color": {k: colour[k] for k in ("default", "lo", "hi")}, "params": entry["params"],
            "options": entry["options"], "views": entry["views"],
            "microfacet_only": entry["refused_views"], "reference": entry["reference"]}
