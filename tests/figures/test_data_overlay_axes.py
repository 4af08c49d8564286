"""An overlay shows the data it exists to show: the value axis of the model's figure is
widened to the data's peak (a MERL-like set peaking at 3.75 was drawn on a lobe axis to
1.47 and an albedo axis sized to the model alone)."""
import numpy as np

from app.figures.data_overlay import with_data
from app.figures.curves import albedo_figure
from app.figures.lobes import lobe_figure

SPEC = {"ndf": "ggx", "alpha": 0.5, "fresnel": "none"}
THETA = np.linspace(-89.0, 89.0, 179)


def _result(axis_name, axis, data, error=None):
    return {"axes": {axis_name: axis}, "data": np.asarray(data, float), "data_error": error,
            "max_relative_error": 1.5, "where": {axis_name: 30.0}}


def _peaked():
    # a model lobe whose peak is 1.47 and data with a sharp peak of 3.75 at the mirror
    model = 1.47 * np.exp(-((THETA - 30.0) / 25.0) ** 2)
    data = model + 2.28 * np.exp(-((THETA - 30.0) / 2.0) ** 2)
    assert np.isclose(data.max(), 3.75)
    return model, data


def test_linear_lobe_radius_reaches_the_data_peak():
    model, data = _peaked()
    fig = lobe_figure({"theta_o_deg": THETA, "f": model}, SPEC, 30.0)
    assert fig["layout"]["polar"]["radialaxis"]["range"][1] < 3.75   # the model's own axis
    both = with_data(fig, _result("theta_o_deg", THETA, data), "(r)")
    top = both["layout"]["polar"]["radialaxis"]["range"][1]
    assert top >= 3.75
    guides = [t for t in both["data"] if (t.get("meta") or {}).get("role") == "guide"]
    assert guides and all(max(t["r"]) >= 3.75 for t in guides)


def test_log_lobe_radius_reaches_the_data_peak():
    model, data = _peaked()
    fig = lobe_figure({"theta_o_deg": THETA, "f": model}, SPEC, 30.0, log=True)
    bottom = fig["layout"]["polar"]["radialaxis"]["range"][0]
    both = with_data(fig, _result("theta_o_deg", THETA, data), "(r)")
    lo, hi = both["layout"]["polar"]["radialaxis"]["range"]
    assert 10 ** hi >= 3.75 and lo == bottom


def test_albedo_axis_covers_data_and_error_bars():
    mu = np.linspace(0.05, 1.0, 20)
    E = np.full_like(mu, 0.3)
    fig = albedo_figure({"mu": mu, "E": E, "E_error": np.full_like(mu, 1e-4), "E_avg": 0.3,
                         "method": "quadrature"}, SPEC)
    lo, hi = fig["layout"]["yaxis"]["range"]
    assert hi < 0.5
    data = E.copy()
    data[-1] = 0.9
    error = np.full_like(mu, 0.05)
    both = with_data(fig, _result("mu", mu, data, error), "(r)")
    lo2, hi2 = both["layout"]["yaxis"]["range"]
    assert hi2 >= 0.95 and lo2 <= lo


def test_axis_not_narrowed_when_data_is_inside():
    model, _ = _peaked()
    fig = lobe_figure({"theta_o_deg": THETA, "f": model}, SPEC, 30.0)
    before = fig["layout"]["polar"]["radialaxis"]["range"]
    both = with_data(fig, _result("theta_o_deg", THETA, 0.5 * model), "(r)")
    assert both["layout"]["polar"]["radialaxis"]["range"] == before


def test_the_difference_on_the_sphere_is_drawn_round():
    """(data − model)/model on the sphere's pixels (both axes in sphere radii) keeps its
    aspect: the y axis is tied to the x axis' scale, and neither is stretched to fill the
    panel (it was drawn as an ellipse the panel's shape)."""
    from app.figures.data_overlay import relative_error
    c = np.linspace(-1.0, 1.0, 9)
    rel = np.where(np.hypot(*np.meshgrid(c, c, indexing="ij")) <= 1.0, 0.1, np.nan)
    fig = relative_error({"axes": {"y": c, "x": c}, "relative_error": rel,
                          "max_relative_error": 0.1, "where": {"y": 0.0, "x": 0.0}}, "(luminance)")
    x, y = fig["layout"]["xaxis"], fig["layout"]["yaxis"]
    assert y.get("scaleanchor") == "x" and y.get("scaleratio", 1) == 1
    assert x.get("constrain") == "domain" and y.get("constrain") == "domain"
    # a curve of one variable has no such tie
    line = relative_error({"axes": {"mu": c}, "relative_error": c, "max_relative_error": 1.0,
                           "where": {"mu": 1.0}}, "(luminance)")
    assert "scaleanchor" not in line["layout"]["yaxis"]
