"""The image panels as a person sees them at 1400 × 900 (issue 34), in one page: the
half/difference slice at the page's default α shows structure (it was one dark colour:
a divergent node set its colour bar), each panel's heading names the diffuse model, and
every image's colour bar labels, legend entries and axis titles stand apart."""
from __future__ import annotations

import pytest

from test_page import wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

IMAGES = ("plot-slice", "plot-sphere")

# The heatmap as drawn (Plotly paints it into an <image>): its pixels' luminance range
# and how many distinct colours it has
PIXELS_JS = """async (id) => {
  const node = document.querySelector(`#${id} .heatmaplayer image`);
  const img = new Image();
  img.src = node.getAttribute('href') || node.getAttribute('xlink:href');
  await img.decode();
  const c = document.createElement('canvas');
  c.width = img.naturalWidth; c.height = img.naturalHeight;
  const g = c.getContext('2d');
  g.drawImage(img, 0, 0);
  const d = g.getImageData(0, 0, c.width, c.height).data;
  let lo = 1, hi = 0;
  const colours = new Set();
  for (let i = 0; i < d.length; i += 4) {
    if (d[i + 3] < 255) continue;                      // a gap (no pair): not drawn
    const y = (0.2126 * d[i] + 0.7152 * d[i + 1] + 0.0722 * d[i + 2]) / 255;
    lo = Math.min(lo, y); hi = Math.max(hi, y);
    colours.add((d[i] >> 3) * 1024 + (d[i + 1] >> 3) * 32 + (d[i + 2] >> 3));
  }
  return { spread: hi - lo, colours: colours.size }; }"""

# Texts that must not run into one another: per plot, colour-bar labels, legend entries,
# and the axis and colour-bar titles against every other text
APART_JS = """(id) => {
  const div = document.getElementById(id), box = (n) => n.getBoundingClientRect();
  const meet = (a, b) => a.left < b.right - 1 && b.left < a.right - 1 && a.top < b.bottom - 1 && b.top < a.bottom - 1;
  const clash = (nodes) => { const out = [];
    for (let i = 0; i < nodes.length; i++) for (let j = i + 1; j < nodes.length; j++)
      if (meet(box(nodes[i]), box(nodes[j]))) out.push([nodes[i].textContent, nodes[j].textContent]);
    return out; };
  const titles = [...div.querySelectorAll('.g-xtitle text, .g-ytitle text, .cbtitle text, .annotation-text')];
  const legend = [...div.querySelectorAll('.legend .traces')];
  return { bar: clash([...div.querySelectorAll('.colorbar .cbaxis text')]), legend: clash(legend),
           titles: clash([...titles, ...legend]) }; }"""


def test_images_show_structure_name_the_diffuse_model_and_keep_their_texts_apart(page, page_log):
    page.set_viewport_size({"width": 1400, "height": 900})
    page.goto("/?show=slice,sphere&diffuse=burley&kd=0.5")
    wait_quiet(page, ids=IMAGES, timeout=60_000)
    slice_pixels = page.evaluate(PIXELS_JS, "plot-slice")
    assert slice_pixels["spread"] > 0.3 and slice_pixels["colours"] >= 30, slice_pixels
    for pid in IMAGES:
        heading = page.locator(f"#{pid}").locator("xpath=ancestor::section").locator("h2").all_text_contents()
        assert any("Burley" in h for h in heading), (pid, heading)
        apart = page.evaluate(APART_JS, pid)
        assert apart == {"bar": [], "legend": [], "titles": []}, (pid, apart)
    assert page_log.problems() == []
