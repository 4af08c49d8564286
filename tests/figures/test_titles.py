"""Titles and file names name every parameter that differs from the defaults, names read
as names, comparison headings as headings, axes fit the data and log axes carry labels."""
import numpy as np
import pytest

from app.figures.curves import albedo_y_range
from app.figures.overlay import overlay
from app.figures.style import log_axis
from app.figures.titles import file_stem, model_title
from app.model import make_spec

CASES = [
    (dict(ndf="gtr", gamma=1.37), "γ=1.37"),
    (dict(ndf="exp_power", p=0.6), "p=0.6"),
    (dict(fresnel="dielectric", ior=1.33), "Dielectric"),
    (dict(fresnel="dielectric", ior=1.33), "η=1.33"),
    (dict(fresnel="none"), "F = 1"),
    (dict(f0=0.9), "F₀=0.9"),
    (dict(kd=0.2), "k_d=0.2"),
    (dict(g2="separable"), "G2 separable"),
    (dict(g2="height_direction_correlated"), "height-direction-correlated"),
    (dict(ndf="beckmann", masking="walter"), "Walter"),
    (dict(multiscatter="kulla_conty"), "Kulla-Conty"),
    (dict(alpha2=0.05, lobe_mix=0.3), "w=0.3"),
]


@pytest.mark.parametrize("given, shown", CASES)
def test_title_and_file_name_carry_what_differs(given, shown):
    values = make_spec(**given).values
    default = make_spec().values
    assert shown in model_title(values)
    assert model_title(values) != model_title(default)
    assert file_stem("lobe", values) != file_stem("lobe", default)
    assert "_" not in model_title(values).replace("k_d", "").replace("α_p", "")


def test_default_title_is_short_and_file_names_are_safe():
    values = make_spec().values
    assert model_title(values) == "GGX α=0.3"
    stem = file_stem("lobe", make_spec(fresnel="dielectric", ior=1.33).values,
                     {"theta_i_deg": 45.5, "n": 181}, {"theta_i_deg": 45.0, "n": 181})
    assert stem == "lobe-ggx-alpha0.3-fresnel-dielectric-ior1.33-theta_i_deg45.5"


def test_titles_of_two_models_that_differ_only_in_one_parameter_differ():
    a = make_spec(ndf="student_t", gamma=3.0).values
    b = make_spec(ndf="student_t", gamma=5.0).values
    assert model_title(a) != model_title(b)


def test_comparison_heading_reads_as_a_heading():
    figs = [{"data": [{"type": "scatter", "x": [0, 1], "y": [0, 1]}],
             "layout": {"title": {"text": f"D(θ_m) — {name}"}}} for name in ("GGX α=0.2", "Beckmann α=0.2")]
    heading = overlay(figs, ["ggx", "beckmann"])["layout"]["title"]["text"]
    assert heading == "D(θ<sub>m</sub>) — ggx vs beckmann"      # θ_m as Plotly's subscript


def test_albedo_axis_fits_the_data_or_spans_zero_to_one():
    E = np.array([0.035, 0.04, 0.05])
    lo, hi = albedo_y_range(E, E, "fit")
    assert lo < 0.035 and hi > 0.05 and hi - lo < 0.05       # the data fills most of the axis
    assert (0.05 - 0.035) / (hi - lo) > 0.6                  # (a 0-1 axis: 0.015)
    assert albedo_y_range(E, E, "unit") == [0.0, 1.05]


@pytest.mark.parametrize("values, want", [([1.0, 20.0], "D1"), ([1.0, 300.0], "D2"), ([1e-8, 1.0], 1)])
def test_log_axes_label_enough_ticks(values, want):
    """Over less than two decades one label a decade is one label; Plotly's "D1" labels
    every digit, "D2" 2 and 5."""
    assert log_axis("y", values, 10)["dtick"] == want


def test_advise_names_models_as_people_do():
    """The advice's title and its table's first column name each choice by its label
    ("Λ Karis", "G2 separable"), not by API names ("masking=karis", "height_correlated")."""
    from app.figures.advise import advise_figure
    spec = make_spec(masking="smith_numeric", fresnel="dielectric").values
    rows = [{"label": "masking=karis", "kind": "single", "changes": {"masking": "karis"},
             "max_error": 0.01, "max_difference": 0.005, "relative_cost": 0.5, "within_tol": True},
            {"label": "g2=separable, fresnel=schlick", "kind": "combination",
             "changes": {"g2": "separable", "fresnel": "schlick"}, "max_error": 0.02,
             "max_difference": 0.01, "relative_cost": 0.4, "within_tol": True}]
    data = {"alternatives": rows, "changes": rows[1]["changes"], "max_error": 0.02,
            "max_difference": 0.01, "relative_cost": 0.4, "tol": 0.05,
            "range": {"alpha_min": 0.05, "alpha_max": 1.0, "theta_max_deg": 90.0}}
    fig = advise_figure(data, spec)
    title = fig["layout"]["title"]["text"]
    names = fig["data"][0]["cells"]["values"][0]
    assert "Λ Smith integral" in title and "F Dielectric" in title and "G2 height-correlated" in title
    assert "Recommended: G2 separable, F Schlick" in title
    assert names[1:] == ["Λ Karis", "G2 separable, F Schlick"]
    for text in [title, *names]:
        assert "=" not in text.replace("F = 1", "") and "_" not in text, text


def test_principled_titles_name_the_principled_parameters():
    """A principled model's titles and file names said "GGX α=0.1225 · G2 separable · F
    Schlick F₀=0.2392": the microfacet form it is built from, not what the user set."""
    default = make_spec(model="principled").values
    metal = make_spec(model="principled", metallic=0.6, roughness=0.35, base_color="0.2,0.4,0.6",
                      lobe="specular").values
    title = model_title(metal)
    assert title.startswith("Principled r=0.35") and "metallic=0.6" in title
    assert "base colour (0.2, 0.4, 0.6)" in title and "Specular lobe" in title
    assert "GGX" not in title and "F₀" not in title
    assert model_title(default) == "Principled r=0.5"
    stem = file_stem("lobe", metal)
    assert stem.startswith("lobe-principled-") and "metallic0.6" in stem and "ggx" not in stem
    assert stem != file_stem("lobe", default)


def test_colour_channels_compared_are_drawn_in_their_own_hues():
    """vary=channel&values=r,g,b drew the red channel in the palette's first colour (blue)."""
    from app.figures.overlay import overlay
    curve = {"data": [{"type": "scatter", "x": [0, 1], "y": [0, 1], "name": "f"}], "layout": {}}
    fig = overlay([curve, curve, curve], ["channel=r", "channel=g", "channel=b"])
    hues = [t["line"]["color"] for t in fig["data"]]
    rgb = [tuple(int(h[i:i + 2], 16) for i in (1, 3, 5)) for h in hues]
    assert rgb[0][0] == max(rgb[0]) and rgb[1][1] == max(rgb[1]) and rgb[2][2] == max(rgb[2])
