"""The principled configurations the generated code is checked on: every option value
(G2 form, diffuse model, multiple scattering, base colour encoding, each lobe alone), with
every parameter away from 0 so that no lobe drops out, and the corners (roughness 0 — α
at its floor 0.001 —, metallic 1, a black base colour, gloss 0 and 1)."""
from __future__ import annotations

from itertools import product

#: Every parameter in play (anisotropic only without Kulla-Conty, which refuses it).
BUSY = {"model": "principled", "base_color": "0.8,0.35,0.1", "metallic": 0.3, "specular": 0.6,
        "specular_tint": 0.4, "roughness": 0.55, "sheen": 0.6, "sheen_tint": 0.7, "clearcoat": 0.8,
        "clearcoat_gloss": 0.7, "subsurface": 0.5}


def principled_models() -> list[dict]:
    out = []
    for g2, diffuse, ms, space in product(("separable", "height_correlated"), ("burley", "lambert", "eon"),
                                          ("none", "kulla_conty"), ("linear", "srgb")):
        out.append({**BUSY, "principled_g2": g2, "principled_diffuse": diffuse, "principled_multiscatter": ms,
                    "base_color_space": space, "anisotropic": 0.5 if ms == "none" else 0.0})
    out += [{**BUSY, "lobe": lobe} for lobe in ("diffuse", "sheen", "specular", "clearcoat")]
    out += [{"model": "principled"},                                  # the paper's defaults
            {"model": "principled", "roughness": 0.0, "clearcoat": 1.0, "clearcoat_gloss": 1.0},
            {"model": "principled", "metallic": 1.0, "roughness": 0.9, "principled_multiscatter": "kulla_conty"},
            {"model": "principled", "base_color": "0,0,0", "sheen": 1.0, "subsurface": 1.0, "clearcoat_gloss": 0.0,
             "clearcoat": 0.5, "principled_diffuse": "eon", "anisotropic": 1.0}]
    return out


def covering_models() -> list[dict]:
    """Fewer programs, for the float32 finiteness check at the horizon
    (tests/e2e/test_gpu_principled.py, its first six): every value of every option at
    least once, each diffuse model with both G2 forms, both encodings and both
    multiple-scattering choices; then the lobes and corners as above. Every option
    against /eval in WebGL2: tests/e2e/test_webgl_full_product.py."""
    rows = [("burley", "separable", "none", "linear"), ("burley", "height_correlated", "kulla_conty", "srgb"),
            ("lambert", "separable", "kulla_conty", "linear"), ("lambert", "height_correlated", "none", "srgb"),
            ("eon", "separable", "none", "srgb"), ("eon", "height_correlated", "kulla_conty", "linear")]
    out = [{**BUSY, "principled_diffuse": d, "principled_g2": g2, "principled_multiscatter": ms,
            "base_color_space": space, "anisotropic": 0.5 if ms == "none" else 0.0} for d, g2, ms, space in rows]
    return out + principled_models()[24:]


#: Two materials one compiled shader draws by its uniforms alone (same options).
TWO_MATERIALS = ({**BUSY, "principled_diffuse": "eon", "anisotropic": 0.4},
                 {"model": "principled", "base_color": "0.1,0.5,0.9", "metallic": 0.9, "specular": 0.2,
                  "specular_tint": 0.0, "roughness": 0.2, "sheen": 0.1, "sheen_tint": 0.0, "clearcoat": 0.3,
                  "clearcoat_gloss": 0.2, "subsurface": 0.0, "principled_diffuse": "eon", "anisotropic": 0.9})


def model_id(params: dict) -> str:
    return ",".join(f"{k}={v}" for k, v in params.items() if k != "model" and (k not in BUSY or params is BUSY))
