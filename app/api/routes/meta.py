"""``GET /api/v1/health`` and ``GET /api/v1/models``: liveness, and every model family of
the registry with its parameters, options, ranges, defaults, the views that draw it and
its albedo methods (what the page builds its model menu and controls from). The default
family's catalogue is also at the top level (the form clients have read since v1)."""
from fastapi import APIRouter

from ... import __version__
from ...model import DEFAULT, families
from ...shader import generate
from ...views import VIEWS
from ..deps import Route

router = APIRouter(prefix="/api/v1", tags=["meta"], route_class=Route)

GEOMETRY = [
    {"name": "theta_i_deg", "label": "θ_i (incidence, degrees)", "lo": 0.0, "hi": 90.0,
     "default": 45.0, "description": "Polar angle of the light direction l.", "lo_open": False,
     "scale": "linear", "unit": "°"},
    {"name": "phi_i_deg", "label": "φ_i (azimuth, degrees)", "lo": -360.0, "hi": 360.0,
     "default": 0.0, "description": "Azimuth of l from the tangent x (direction of α_x).",
     "lo_open": False, "scale": "linear", "unit": "°"},
]


@router.get("/health", summary="Liveness and version",
            responses={200: {"content": {"application/json": {"example": {"status": "ok", "version": "0.1.0"}}}}})
def health():
    return {"status": "ok", "version": __version__}


def family_entry(family) -> dict:
    """One family as /models lists it: its catalogue, the views that draw it (and why the
    others do not), its albedo methods."""
    refused = {name: why for name in VIEWS if (why := family.views(name)) is not None}
    return {"name": family.name, "label": family.label, "description": family.description,
            "reference": family.reference, **family.catalogue(),
            "views": [name for name in VIEWS if name not in refused], "refused_views": refused,
            "albedo_methods": list(family.albedo_methods), "shader": generate.writes(family),
            "default": family.name == DEFAULT}


@router.get("/models", summary="Every model family, option and parameter with ranges and defaults",
            responses={200: {"content": {"application/json": {"example": {
                "version": "0.1.0",
                "params": [{"name": "alpha", "label": "α (roughness, x)", "lo": 0.0001, "hi": 1.0,
                            "default": 0.3, "scale": "log", "unit": ""}],
                "geometry": [{"name": "theta_i_deg", "lo": 0.0, "hi": 90.0, "default": 45.0, "unit": "°"}],
                "options": {"ndf": {"label": "Normal distribution D", "default": "ggx",
                                    "choices": [{"name": "ggx", "label": "GGX (Trowbridge-Reitz)",
                                                 "params": []}]}},
                "models": [{"name": "microfacet", "label": "Microfacet model", "views": ["lobe"],
                            "refused_views": {}, "albedo_methods": ["quadrature"]}]}}}}})
def models():
    found = families()
    return {"version": __version__, **found[DEFAULT].catalogue(), "geometry": GEOMETRY,
            "models": [family_entry(f) for f in found.values()]}
