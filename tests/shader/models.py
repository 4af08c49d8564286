"""The registry models the generated code is checked on: every NDF × masking × G2 form
that the model accepts, each Fresnel, both λ(φ), anisotropy, two lobes, Kulla-Conty,
and the shape parameters at their special points."""
from __future__ import annotations

from app.errors import ParameterError
from app.model import make_spec
from app.physics.g2 import G2_FORMS
from app.physics.masking import MASKINGS
from app.physics.ndf import NDFS


def _accepted(params: dict) -> bool:
    try:
        make_spec(**params)
    except ParameterError:
        return False
    return True


def registry_models() -> list[dict]:
    out = []
    for ndf in NDFS:
        for masking in MASKINGS:
            for g2 in G2_FORMS:
                params = {"ndf": ndf, "masking": masking, "g2": g2, "alpha": 0.35}
                if _accepted(params):
                    out.append(params)
    out += [{"ndf": "ggx", "alpha": 0.3, "fresnel": f} for f in ("none", "schlick", "dielectric", "conductor")]
    out += [{"ndf": "beckmann", "alpha": 0.3, "g2": g2, "lambda_phi": "van_ginneken"}
            for g2 in ("direction_correlated", "height_direction_correlated")]
    out += [{"ndf": ndf, "alpha": 0.25, "alpha_y": 0.5} for ndf in ("ggx", "beckmann", "student_t", "exp_power")]
    out += [{"ndf": "ggx", "roughness": 0.6, "anisotropy": 0.5, "aniso_map": "kulla_conty", "g2": "separable"},
            {"ndf": "ggx", "alpha": 0.3, "alpha2": 0.6, "lobe_mix": 0.3, "kd": 0.2},
            {"ndf": "gtr", "gamma": 1.2, "alpha": 0.3, "alpha2": 0.7, "lobe_mix": 0.5},
            {"ndf": "gtr", "gamma": 1.0, "alpha": 0.4}, {"ndf": "gtr", "gamma": 2.0, "alpha": 1.0},
            {"ndf": "student_t", "gamma": 1.6, "alpha": 0.3}, {"ndf": "student_t", "gamma": 2.0, "alpha": 0.3},
            {"ndf": "student_t", "gamma": 50.0, "alpha": 0.3},
            {"ndf": "exp_power", "p": 0.5, "alpha": 0.3}, {"ndf": "exp_power", "p": 2.0, "alpha": 0.3},
            {"ndf": "blinn_phong", "alpha": 1.0}, {"ndf": "ggx", "alpha": 1.0, "fresnel": "dielectric", "ior": 2.4},
            {"ndf": "ggx", "alpha": 0.5, "multiscatter": "kulla_conty"},
            {"ndf": "ggx", "alpha": 0.8, "multiscatter": "kulla_conty", "fresnel": "conductor", "alpha2": 0.2,
             "lobe_mix": 0.4},
            {"ndf": "beckmann", "alpha": 0.6, "multiscatter": "kulla_conty", "g2": "separable", "fresnel": "dielectric"},
            {"ndf": "ggx", "alpha": 0.3, "material": "gold"},
            {"ndf": "ggx", "alpha": 0.5, "material": "copper", "multiscatter": "kulla_conty"},
            {"ndf": "beckmann", "alpha": 0.3, "material": "water", "kd": 0.1}]
    return out


def model_id(params: dict) -> str:
    return ",".join(f"{k}={v}" for k, v in params.items())
