"""GET /api/v1/principled: the principled BRDF's parameters, ranges, defaults and options,
and which views take it (what the page builds its controls and panels from). Its own
views — principled_albedo, sphere_env — are views like any other (app/views/)."""
from __future__ import annotations

from fastapi import APIRouter

from ...principled.params import BASE_COLOR_DEFAULT, OPTIONS, PARAMS
from ...principled.spec import ROUGHNESS
from ...views import VIEWS
from ..deps import Route

router = APIRouter(prefix="/api/v1", route_class=Route)

#: Views that refuse model=principled (422 naming ``model``), and why: each varies the
#: microfacet model's own choices, which the principled model fixes.
MICROFACET_ONLY = {
    "advise": "It searches for cheaper microfacet choices (D, G2, Fresnel, α) for a scene; "
              "the principled model fixes those.",
    "checks": "Its identities vary the microfacet model's own terms (G2, Fresnel, k_d); "
              "the principled model fixes those.",
}
#: Choices for isotropic roughness only (anisotropic = 0): the API refuses them otherwise.
ISOTROPIC_ONLY = {("principled_multiscatter", "kulla_conty")}


def _choice(option: str, c) -> dict:
    out = {"name": c.name, "label": c.label, "description": c.description}
    if (option, c.name) in ISOTROPIC_ONLY:
        out["isotropic_only"] = True
    return out


@router.get("/principled", tags=["meta"], summary="The principled BRDF's parameters and options",
            responses={200: {"content": {"application/json": {"example": {
                "base_color": {"default": [0.82, 0.67, 0.16], "lo": 0.0, "hi": 1.0},
                "params": [{"name": "metallic", "lo": 0.0, "hi": 1.0, "default": 0.0}],
                "options": {"lobe": {"label": "Lobe shown", "default": "all", "choices": []}},
                "views": ["lobe", "sphere_env"], "microfacet_only": {"checks": "why"},
                "reference": "Burley 2012"}}}}})
def principled_catalogue():
    return {"base_color": {"default": list(BASE_COLOR_DEFAULT), "lo": 0.0, "hi": 1.0},
            "params": [ROUGHNESS.as_dict()] + [p.as_dict() for p in PARAMS],
            "options": {name: {"label": label, "default": default,
                               "choices": [_choice(name, c) for c in choices.values()]}
                        for name, (label, choices, default) in OPTIONS.items()},
            "views": [name for name in VIEWS if name not in MICROFACET_ONLY],
            "microfacet_only": MICROFACET_ONLY,
            "reference": "Burley 2012, Physically-Based Shading at Disney; docs/principled.md"}
