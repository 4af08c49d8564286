"""The principled BRDF lobe by lobe against disney.brdf (tests/principled/references.py),
its reciprocity, its parameter edges, and E ≤ 1 for metals with Kulla-Conty."""
from __future__ import annotations

import numpy as np
import pytest

from app.principled import LOBES, Principled, principled_brdf

from .references import DEFAULTS, disney

SETTINGS = [
    {},
    dict(base_color=(0.9, 0.3, 0.1), metallic=0.3, specular=0.8, specular_tint=0.6, roughness=0.35,
         anisotropic=0.7, sheen=0.8, sheen_tint=0.4, clearcoat=0.9, clearcoat_gloss=0.3, subsurface=0.6),
    dict(base_color=(0.2, 0.5, 0.95), metallic=1.0, roughness=0.9, clearcoat=1.0, clearcoat_gloss=0.0),
]


def _pairs(n=300, seed=2):
    rng = np.random.default_rng(seed)
    th = rng.uniform(0.0, 0.47 * np.pi, (2, n))
    ph = rng.uniform(-np.pi, np.pi, (2, n))
    d = np.stack([np.sin(th) * np.cos(ph), np.sin(th) * np.sin(ph), np.cos(th)], axis=-1)
    return d[0], d[1]


@pytest.mark.parametrize("s", SETTINGS)
@pytest.mark.parametrize("lobe", ["all", *LOBES])
def test_lobe_against_disney_brdf(s, lobe):
    p = {**DEFAULTS, **s}
    m = Principled(**p)
    l, v = _pairs()
    got = m.f_rgb(l, v, lobe)
    want = np.array([disney(a, b, p, lobe) for a, b in zip(l, v)])
    np.testing.assert_allclose(got, want, rtol=1e-10, atol=1e-13)


@pytest.mark.parametrize("s", SETTINGS)
def test_reciprocity(s):
    """The paper's model is reciprocal: every lobe depends on l and v symmetrically
    (μ_l, μ_v through symmetric products, θ_d, h)."""
    m = Principled(**{**DEFAULTS, **s})
    l, v = _pairs(seed=4)
    np.testing.assert_allclose(m.f_rgb(l, v), m.f_rgb(v, l), rtol=1e-12)


NAMES = ["metallic", "specular", "specular_tint", "roughness", "anisotropic", "sheen", "sheen_tint",
         "clearcoat", "clearcoat_gloss", "subsurface"]


@pytest.mark.parametrize("value", [0.0, 1.0])
def test_every_parameter_edge_finite(value):
    """Each parameter at 0 and at 1 (the others at their defaults), all at 0, all at 1, and
    black and white base colours: f finite and ≥ 0 up to the horizon (one direction at
    a time), and the lobes' albedos finite."""
    from app.principled.albedo import lobe_albedo
    theta = np.deg2rad([0.0, 45.0, 89.0, 90.0])
    tl, tv, dphi = np.meshgrid(theta, theta, np.deg2rad([0.0, 90.0, 180.0]), indexing="ij")
    keep = ~((tl == np.pi / 2) & (tv == np.pi / 2))
    l = np.stack([np.sin(tl), 0 * tl, np.cos(tl)], axis=-1)
    v = np.stack([np.sin(tv) * np.cos(dphi), np.sin(tv) * np.sin(dphi), np.cos(tv)], axis=-1)
    cases = [{n: value} for n in NAMES] + [dict.fromkeys(NAMES, value)]
    cases += [dict(base_color=(value,) * 3, **dict.fromkeys(NAMES, value))]
    for case in cases:
        m = Principled(**{**DEFAULTS, **case})
        f = m.f_rgb(l, v)[keep]
        assert np.all(np.isfinite(f)) and np.all(f >= 0), case
        for E, err in lobe_albedo(m, np.array([0.05, 0.5, 1.0])).values():
            assert np.all(np.isfinite(E)) and np.isfinite(err), case


def test_metal_with_kulla_conty_conserves():
    """metallic = 1: without compensation a rough metal loses energy; with the per-channel
    Kulla-Conty lobe E ≤ 1 (to the table's error) and a white metal reflects all of it."""
    from app.principled.albedo import lobe_albedo
    mu = np.array([0.1, 0.4, 0.8, 1.0])
    white = dict(base_color=(1.0, 1.0, 1.0), metallic=1.0, roughness=1.0)
    single = Principled(**{**DEFAULTS, **white})
    E1, _ = lobe_albedo(single, mu)["specular"]
    assert np.all(E1 < 0.9)
    opts = {"principled_g2": "height_correlated", "principled_diffuse": "burley",
            "principled_multiscatter": "kulla_conty", "base_color_space": "linear"}
    for base in [(1.0, 1.0, 1.0), (0.95, 0.64, 0.54)]:
        for r in (0.2, 0.6, 1.0):
            m = Principled(**{**DEFAULTS, **white, "base_color": base, "roughness": r}, options=opts)
            E, err = lobe_albedo(m, mu)["specular"]
            assert np.all(E <= 1.0 + err + 1e-4), (base, r, E)
            if base == (1.0, 1.0, 1.0):
                np.testing.assert_allclose(E, 1.0, atol=err + 1e-3)


def test_brdf_channel_and_lobe_selection():
    m = Principled(**{**DEFAULTS, **SETTINGS[1]})
    l, v = _pairs(n=20, seed=9)
    rgb = m.f_rgb(l, v, "sheen")
    b = principled_brdf(m, lobe="sheen", channel_name="g")
    np.testing.assert_allclose(b.evaluate(l, v)["f"], rgb[:, 1])
    lum = principled_brdf(m).evaluate(l, v, ("f", "f_rgb"))
    np.testing.assert_allclose(lum["f"], lum["f_rgb"] @ [0.2126, 0.7152, 0.0722])
