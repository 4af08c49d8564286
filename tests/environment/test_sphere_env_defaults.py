"""The environment sphere as a slide (issue 34): at its defaults at least 256 px, the
environment behind the sphere rather than a flat colour, the material in the title and no
timing anywhere in it (the same query gives the same figure)."""
from __future__ import annotations

import base64
import re

import numpy as np

from app.config import Settings
from app.figures.sphere_image import srgb_encode
from app.lut import png
from app.views import VIEWS, run


def _figure(**params) -> dict:
    view = VIEWS["sphere_env"]
    return run(view, view.figure_query(**params), Settings()).figure()


def _pixels(figure: dict) -> np.ndarray:
    source = figure["data"][0]["source"]
    return png.read(base64.b64decode(source.split(",", 1)[1]))[0]


def test_the_default_image_is_at_least_256_pixels_across():
    assert VIEWS["sphere_env"].figure_query().n >= 256
    image = _pixels(_figure(n=24, samples=4))
    assert image.shape[:2] == (24, 24)                 # the picture is n × n


def test_the_environment_is_behind_the_sphere():
    """Sunset: the corners above the horizon show the sky, the ones below the ground —
    the sky's own colours (maps.py: horizon + t (zenith − horizon), t = y^0.4; ground),
    not one flat colour."""
    n = 32
    image = _pixels(_figure(environment="sunset", n=n, samples=4)).astype(float)
    top, bottom = image[0, 0, :3], image[n - 1, 0, :3]
    ground = np.round(srgb_encode(np.array([0.04, 0.03, 0.025])) * 255)
    assert np.abs(bottom - ground).max() <= 1
    assert top[2] > top[0] and np.abs(top - ground).max() > 40   # blue sky above, not the ground


def test_the_title_names_the_material_and_no_timing():
    figure = _figure(material="gold", alpha=0.2, environment="overcast", n=16, samples=4)
    title = figure["layout"]["title"]["text"]
    assert "gold" in title.lower() and "0.2" in title and "Overcast" in title
    assert not re.search(r"\d\s*s\b|seconds", title), title
    again = _figure(material="gold", alpha=0.2, environment="overcast", n=16, samples=4)
    assert again["layout"]["title"]["text"] == title
