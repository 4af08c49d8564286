"""At a slide's 1600×1000 the legends of the curve figures sit clear of their axis titles
(the SVG that kaleido renders: the legend's box against the x-axis title's baseline)."""
import re
import shutil

import pytest

FIGURES = ["g1?alpha=0.2", "g1?ndf=beckmann&masking=walter", "albedo?fresnel=schlick",
           "fresnel", "albedo?multiscatter=kulla_conty&fresnel=none"]


@pytest.mark.skipif(shutil.which("chromium") is None and shutil.which("chromium-browser") is None,
                    reason="needs a Chromium for kaleido")
@pytest.mark.parametrize("figure", FIGURES)
def test_legend_clear_of_the_x_axis_title(client, figure):
    path, _, query = figure.partition("?")
    r = client.get(f"/api/v1/figures/{path}.svg?{query}&width=1600&height=1000")
    assert r.status_code == 200, r.text
    svg = r.text
    legend = re.search(r'<g class="legend"[^>]*translate\(([-\d.]+),([-\d.]+)\)".*?<rect class="bg"[^>]*'
                       r'height="([\d.]+)"', svg, flags=re.S)
    title = re.search(r'<text class="xtitle"[^>]*y="([\d.]+)"[^>]*font-size: ([\d.]+)px', svg)
    assert legend and title
    legend_top, legend_bottom = float(legend.group(2)), float(legend.group(2)) + float(legend.group(3))
    title_bottom = float(title.group(1)) + 0.3 * float(title.group(2))   # baseline + descenders
    title_top = float(title.group(1)) - float(title.group(2))
    assert legend_top > title_bottom or legend_bottom < title_top, (legend_top, title_bottom)
    assert legend_bottom <= 1000
