"""``GET /api/v1/health`` and ``GET /api/v1/models``: liveness, and every option of the
model with its parameters, ranges and defaults (what the page builds its controls from)."""
from fastapi import APIRouter

from ... import __version__
from ...model import COMMON_PARAMS, OPTIONAL_PARAMS, OPTIONS, SUB_OPTIONS, choice_params
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


def _choice(option: str, name: str, entry) -> dict:
    out = {"name": name, "label": entry.label, "description": entry.description,
           "params": [p.as_dict() for p in choice_params(option, name)]}
    for attr in ("reference", "applies_to", "anisotropic", "isotropic_only", "needs_phi",
                 "approximation", "derived_doc"):
        if hasattr(entry, attr):
            out[attr] = getattr(entry, attr)
    return out


@router.get("/models", summary="Every option with its parameters, ranges and defaults",
            responses={200: {"content": {"application/json": {"example": {
                "version": "0.1.0",
                "params": [{"name": "alpha", "label": "α (roughness, x)", "lo": 0.0001, "hi": 1.0,
                            "default": 0.3, "scale": "log", "unit": ""}],
                "geometry": [{"name": "theta_i_deg", "lo": 0.0, "hi": 90.0, "default": 45.0, "unit": "°"}],
                "options": {"ndf": {"label": "Normal distribution D", "default": "ggx",
                                    "choices": [{"name": "ggx", "label": "GGX (Trowbridge-Reitz)",
                                                 "params": []}]}}}}}}})
def models():
    return {
        "version": __version__,
        "params": [{**p.as_dict(), "optional": p.name in OPTIONAL_PARAMS} for p in COMMON_PARAMS],
        "geometry": GEOMETRY,
        "options": {
            option: {"label": label, "default": default,
                     "choices": [_choice(option, name, entry) for name, entry in registry.items()]}
            for option, (label, registry, default) in OPTIONS.items()
        },
        "sub_options": {
            name: {"label": label, "default": default, "applies_with": when,
                   "choices": [{"name": key, "label": entry.label, "description": entry.description}
                               for key, entry in registry.items()]}
            for name, (label, registry, default, _, when) in SUB_OPTIONS.items()
        },
    }
