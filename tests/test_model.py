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


def test_query_names_follow_the_registries():
    """A family's query names are kept between requests (Family.own_names) until a
    registry changes: a Fresnel registered after they were read brings its parameter,
    which make_spec then takes; unregistered, the parameter is refused again."""
    import numpy as np

    from app.model.registry import family_of
    from app.physics.fresnel.base import FRESNELS, Fresnel
    from app.physics.params import Param

    family = family_of({})
    assert "f_memo_test" not in family.own_names()            # read: now kept

    class Flat(Fresnel):
        name = "flat_memo_test"
        label = "Flat (test)"
        description = "F = F_c at every angle, for a test."
        params = (Param("f_memo_test", "F_c", 0.0, 1.0, 0.5, "The constant reflectance."),)
        menu_order = 99

        def F(self, cos_theta_d):
            return np.full(np.shape(cos_theta_d), self.f_memo_test)

        def F_avg(self):
            return self.f_memo_test

    FRESNELS.register(Flat)
    try:
        assert "f_memo_test" in family.own_names()
        spec = make_spec(fresnel="flat_memo_test", f_memo_test=0.25)
        assert spec.values["f_memo_test"] == 0.25
    finally:
        FRESNELS.unregister("flat_memo_test")
    assert "f_memo_test" not in family.own_names()
    with pytest.raises(ParameterError):
        make_spec(f_memo_test=0.25)
