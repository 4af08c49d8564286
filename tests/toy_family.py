"""A throwaway model family, written into a directory at test time: Lambert plus a
Phong lobe (Blinn's form on half vectors, a microfacet NDF: Walter et al. 2007, eq. 30;
Blinn 1977) with two parameters, in ONE package (``lambert_phong/family.py``). The
application finds it through BRDF_MODEL_DIRS (app/model/registry.py) with no file of
app/ or static/ edited: what the issue-31 test asks of the model registry."""
from __future__ import annotations

import textwrap
from pathlib import Path

NAME = "lambert_phong"

FAMILY_SOURCE = textwrap.dedent('''
    """Lambert plus a Phong lobe: f = rho_d/pi + D_Phong(h) G2 / (4 mu_l mu_v), F = 1."""
    from typing import Optional

    import numpy as np

    from app.errors import ParameterError
    from app.model.family import Family, check_range, only_views, param_fields
    from app.physics.brdf import BRDF
    from app.physics.fresnel import FRESNELS
    from app.physics.g2 import G2_FORMS
    from app.physics.masking import MASKINGS
    from app.physics.ndf import NDFS
    from app.physics.params import Param

    NAME = "lambert_phong"
    RHO_D = Param("rho_d", "rho_d (diffuse albedo)", 0.0, 1.0, 0.4, "Lambert's albedo: f_d = rho_d/pi.")
    SHININESS = Param("shininess", "n (Phong exponent)", 1.0, 2000.0, 40.0,
                      "Phong exponent n of D = (n + 2)/(2 pi) cos^n theta_h.", scale="log")
    PARAMS = (RHO_D, SHININESS)


    def make_values(given):
        for name in given:
            if name not in (RHO_D.name, SHININESS.name):
                raise ParameterError(name, f"{name} does not apply to model={NAME}")
        return {"model": NAME, **{p.name: check_range(p, given.get(p.name, p.default)) for p in PARAMS}}


    def brdf(values):
        # Walter et al. 2007, eq. 33: the Beckmann-equivalent alpha of Phong's exponent
        alpha = float(np.sqrt(2.0 / (values["shininess"] + 2.0)))
        return BRDF(NDFS["blinn_phong"](alpha, None), MASKINGS["smith"], G2_FORMS["height_correlated"],
                    FRESNELS["none"](), values["rho_d"])


    FAMILY = Family(
        NAME, "Lambert + Phong (toy)", "A throwaway family: Lambert plus a Phong lobe.", "Blinn 1977",
        make_values, brdf, lambda v: {p.name: v[p.name] for p in PARAMS},
        lambda: param_fields(PARAMS, NAME), lambda: {"params": [p.as_dict() for p in PARAMS], "options": {}},
        views=only_views(("lobe", "lobe3d", "sphere", "slice", "ndf", "albedo"),
                         "the toy family draws its lobe, its NDF, its sphere and its albedo only"),
        albedo_methods=("quadrature", "mc_uniform", "mc_cosine"))
''')


def write_family(directory: Path) -> Path:
    """The toy package under ``directory`` (what BRDF_MODEL_DIRS then names)."""
    package = directory / NAME
    package.mkdir(parents=True, exist_ok=True)
    (package / "__init__.py").write_text('"""A toy model family (tests/toy_family.py)."""\n')
    (package / "family.py").write_text(FAMILY_SOURCE)
    return directory
