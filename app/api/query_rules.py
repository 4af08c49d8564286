"""Rules about a query that its schema cannot state, shared by routes outside the views
(whose rules are their View limits)."""
from __future__ import annotations

from ..errors import ParameterError
from ..views import schemas


def one_isotropic_lobe(q: schemas.ModelQuery, what: str, compensation: bool) -> None:
    """Refuse, naming the parameter that makes it so, a model with anisotropic roughness,
    a weighted second lobe or (``compensation``) multiple-scattering compensation."""
    brdf = schemas.spec_of(q).brdf()
    given = q.model_fields_set
    if not brdf.ndf.isotropic:
        param = next((p for p in ("alpha_y", "anisotropy") if p in given), "alpha_y")
        raise ParameterError(param, f"{what} is for isotropic roughness (no alpha_y or anisotropy)")
    if brdf.lobe2 is not None and brdf.lobe_mix > 0:
        raise ParameterError("lobe_mix", f"{what} is for one lobe (lobe_mix = 0)")
    if compensation and getattr(brdf, "multiscatter", None) is not None:
        raise ParameterError("multiscatter", f"{what} is for single scattering (multiscatter=none)")


