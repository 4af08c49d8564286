"""Data on the views' axes: a MERL table of a known model lies on that model's curves
and images; scattered samples and term data where they were taken; the figures."""
import types

import numpy as np
import pytest

from app import quantities
from app.environment.sphere import lit_sphere, point_light
from app.figures import data_overlay as figure
from app.datasets import formats, overlay, summary
from app.errors import ParameterError
from app.model import make_spec

from . import known

Q = types.SimpleNamespace(theta_i_deg=30.0, phi_i_deg=0.0, phi_h_deg=0.0, phi_d_deg=90.0, n=32,
                          phi_deg=0.0)


@pytest.fixture(scope="module")
def merl_data():
    return formats.load(known.merl_bytes())


@pytest.fixture(scope="module")
def brdf():
    return make_spec(**known.model("r")).brdf()


@pytest.mark.parametrize("view, arrays", [
    ("lobe", lambda b: quantities.lobe_curve(b, 30.0, 0.0, 181, False)),
    ("lobe3d", lambda b: quantities.lobe_grid(b, 30.0, 0.0, 19, 37)),
    ("slice", lambda b: quantities.half_difference_slice(b, 0.0, 90.0, 46, False)),
    ("sphere", lambda b: lit_sphere(b, point_light(30.0, 0.0), 32, rgb=False)),
])
def test_the_table_of_a_model_lies_on_its_view(merl_data, brdf, view, arrays):
    """Away from grazing the interpolated table is the model to ~0.1 % (the format's 1°
    cells, interpolated linearly); the closed form, not the table's own code, decides."""
    model_arrays = arrays(brdf)
    out = overlay.OVERLAYS[view](merl_data, brdf, model_arrays, Q, "r")
    assert out["compared"] > 100
    rel = np.abs(out["relative_error"][np.isfinite(out["relative_error"])])
    assert np.median(rel) < 2e-3
    assert out["max_relative_error"] == pytest.approx(
        np.nanmax(np.abs(out["relative_error"])) * np.sign(out["max_relative_error"]))


def test_lobe_values_are_the_closed_form(merl_data, brdf):
    arrays = quantities.lobe_curve(brdf, 30.0, 0.0, 181, False)
    out = overlay.lobe(merl_data, brdf, arrays, Q, "r")
    theta_o = out["axes"]["theta_o_deg"]
    inside = np.abs(theta_o) < 70
    t = np.radians(np.abs(theta_o[inside]))
    phi = np.where(theta_o[inside] >= 0, np.pi, 0.0)
    v = np.stack([np.sin(t) * np.cos(phi), np.zeros_like(t), np.cos(t)], -1)
    l = np.array([np.sin(np.radians(30)), 0, np.cos(np.radians(30))])
    np.testing.assert_allclose(out["data"][inside], known.ggx_f(np.broadcast_to(l, v.shape), v),
                               rtol=0.02)


def test_albedo_of_the_data_with_its_error_bars(merl_data, brdf):
    out = overlay.albedo(merl_data, brdf, {}, Q, "r", summary.summarize(merl_data))
    assert list(out["axes"]["mu"]) == list(summary.MU)
    assert (np.abs(out["data"] - out["model"]) <= out["data_error"]).all()


def test_samples_in_the_plane_of_incidence(brdf):
    rows = ["theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f"]
    for ti in (30.0, 45.0):
        for to in (0.0, 20.0, 40.0):
            for po in (0.0, 90.0, 180.0):
                l = np.array([np.sin(np.radians(ti)), 0, np.cos(np.radians(ti))])
                v = np.array([np.sin(np.radians(to)) * np.cos(np.radians(po)),
                              np.sin(np.radians(to)) * np.sin(np.radians(po)), np.cos(np.radians(to))])
                rows.append(f"{ti},0,{to},{po},{float(known.ggx_f(l, v)):.17g}")
    data = formats.load("\n".join(rows).encode())
    out = overlay.lobe(data, brdf, {"theta_o_deg": np.zeros(1), "f": np.zeros(1)}, Q, "f")
    # θ_o = 0 is in every plane (its three rows: φ_o = 0, 90, 180), ±20°, ±40° (φ_o = 90° is not)
    assert sorted(np.round(out["axes"]["theta_o_deg"], 9)) == [-40, -20, 0, 0, 0, 20, 40]
    assert abs(out["max_relative_error"]) < 1e-12


def test_term_data_on_its_view(brdf):
    theta = np.linspace(0, 85, 18)
    t = np.radians(theta)
    D = known.ALPHA ** 2 / (np.pi * (np.cos(t) ** 2 * (known.ALPHA ** 2 - 1) + 1) ** 2)
    data = formats.load(("theta_deg,D\n" + "\n".join(f"{a:.17g},{d:.17g}" for a, d in zip(theta, D))).encode())
    out = overlay.OVERLAYS["ndf"](data, brdf, {"theta_deg": theta, "D": D}, Q, None)
    assert abs(out["max_relative_error"]) < 1e-12
    with pytest.raises(ParameterError, match="term CSV with G1"):
        overlay.OVERLAYS["g1"](data, brdf, {}, Q, None)


def test_views_refuse_data_they_cannot_show(merl_data, brdf):
    samples = formats.load(b"theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n30,0,30,180,1\n")
    with pytest.raises(ParameterError, match="overlays a MERL table") as info:
        overlay.OVERLAYS["slice"](samples, brdf, {}, Q, None)
    assert info.value.param == "data"
    with pytest.raises(ParameterError, match="term CSV with D"):
        overlay.OVERLAYS["ndf"](merl_data, brdf, {}, Q, "r")


def test_figures_add_the_data_and_show_the_relative_error(merl_data, brdf):
    from app.figures.lobes import lobe_figure
    arrays = quantities.lobe_curve(brdf, 30.0, 0.0, 91, False)
    out = overlay.lobe(merl_data, brdf, arrays, Q, "r")
    model_fig = lobe_figure(arrays, known.model("r"), 30.0)
    both = figure.with_data(model_fig, out, "(r)")
    assert len(both["data"]) == len(model_fig["data"]) + 1
    assert both["data"][-1]["name"] == "data (r)" and both["data"][-1]["mode"] == "markers"
    np.testing.assert_array_equal(both["data"][-1]["theta"], arrays["theta_o_deg"])
    assert "largest" in both["layout"]["title"]["text"]
    error = figure.relative_error(out, "(r)")
    assert error["data"][0]["type"] == "scatter"
    assert f"{100 * out['max_relative_error']:+.2f} %" in error["layout"]["title"]["text"]
