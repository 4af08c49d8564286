"""ModelSpec's typed edits: each result is validated like a request, parameters of a
replaced choice go, and the BRDF is built once per spec."""
from __future__ import annotations

import pytest

from app.errors import ParameterError
from app.model import make_spec


def test_as_query_round_trips_and_resolves_the_roughness_form():
    spec = make_spec(roughness=0.5, anisotropy=0.3, fresnel="schlick", f0=0.1)
    query = spec.as_query()
    assert "roughness" not in query and "anisotropy" not in query
    assert query["alpha"] == pytest.approx(0.25 / (1 - 0.27) ** 0.5)      # Burley's map
    again = make_spec(**query)
    assert again.values["alpha"] == spec.values["alpha"] and again.values["f0"] == 0.1


def test_with_drops_the_parameters_of_a_replaced_choice():
    spec = make_spec(fresnel="schlick", f0=0.2, g2="direction_correlated", lambda_phi="ashikhmin")
    dielectric = spec.with_(fresnel="dielectric")
    assert "f0" not in dielectric.as_query() and dielectric.values["fresnel"] == "dielectric"
    separable = spec.with_(g2="separable")
    assert separable.values.get("lambda_phi") is None and separable.values["f0"] == 0.2
    with pytest.raises(ParameterError) as err:
        spec.with_(ndf="gtr", alpha_y=0.1)
    assert err.value.param == "alpha_y"


def test_at_alpha_is_isotropic_and_keeps_everything_else():
    spec = make_spec(ndf="beckmann", alpha=0.1, alpha_y=0.4, kd=0.2)
    at = spec.at_alpha(0.05)
    assert at.values["alpha"] == 0.05 and at.values["alpha_y"] is None
    assert at.values["ndf"] == "beckmann" and at.values["kd"] == 0.2
    assert at.brdf().ndf.alpha_x == at.brdf().ndf.alpha_y == 0.05


def test_the_brdf_is_built_once_per_spec():
    spec = make_spec(alpha=0.2)
    assert spec.brdf() is spec.brdf()
    assert spec.key() == make_spec(alpha=0.2).key() != make_spec(alpha=0.3).key()
