"""Data on the page: a shader's dump dropped on the page shows on the lobe beside the
model, the difference toggle shows its largest error where the bug predicts; a
measured-looking MERL file opened, fitted, and its fit loaded into the controls.

Takes screenshot-data.png (into the `shots` directory): the measured-looking data beside its fitted model.
"""
from __future__ import annotations

import json
import math
import re
import urllib.request

import numpy as np
import pytest
from playwright.sync_api import expect

from test_page import wait_quiet   # tests/e2e is not a package

from tests.datasets import known

pytestmark = pytest.mark.e2e

OVERLAID = "(id) => document.getElementById(id)?.dataset.overlay === 'data'"
DIFFERENCE = "(id) => document.getElementById(id)?.dataset.overlay === 'difference'"


def plot(page, name: str) -> dict:
    """The trace names of a panel's plot and the largest error the data module found."""
    return json.loads(page.evaluate(f"""() => {{ const d = document.getElementById('plot-{name}');
        return JSON.stringify({{names: d.data.map((t) => t.name), title: d.dataset.largest}}); }}"""))


def buggy_dump(base_url: str, theta_i: float) -> str:
    """The page's default model as a shader that forgot 1/(4 n·l n·v) would print it: the
    samples CSV of the model (GET /export/model.csv), each f times 4 cos θ_i cos θ_o."""
    with urllib.request.urlopen(f"{base_url}/api/v1/export/model.csv?n_theta=19&n_phi=24") as res:
        rows = np.loadtxt(res, delimiter=",", skiprows=1)
    assert theta_i in set(rows[:, 0])
    rows[:, 4] *= 4 * np.cos(np.radians(rows[:, 0])) * np.cos(np.radians(rows[:, 2]))
    lines = ["theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f"]
    lines += [",".join(f"{x:.17g}" for x in row) for row in rows]
    return "\n".join(lines) + "\n"


def test_a_dropped_dump_shows_on_the_lobe_and_its_error_where_the_bug_predicts(page, page_log, base_url):
    page.goto("/?show=lobe,albedo")
    wait_quiet(page, ids=("plot-lobe", "plot-albedo"))
    theta_i = page.evaluate("() => window.__brdf.state.theta_i_deg")
    text = buggy_dump(base_url, theta_i)
    page.evaluate("""([name, text]) => {
        const dt = new DataTransfer();
        dt.items.add(new File([text], name, { type: "text/csv" }));
        const target = document.getElementById("panels");
        for (const type of ["dragenter", "dragover", "drop"])
          target.dispatchEvent(new DragEvent(type, { bubbles: true, cancelable: true, dataTransfer: dt }));
    }""", ["shader_dump.csv", text])
    page.wait_for_function(OVERLAID, arg="plot-lobe", timeout=30_000)
    lobe = plot(page, "lobe")
    assert "data (f)" in lobe["names"] and "largest" in lobe["title"]
    assert "samples_csv" in page.text_content("#data-status")
    page.check("#data-difference")
    page.wait_for_function(DIFFERENCE, arg="plot-lobe", timeout=30_000)
    predicted = 100 * (4 * math.cos(math.radians(theta_i)) - 1)     # at θ_o = 0: 4 μ_l μ_v − 1
    title = plot(page, "lobe")["title"]
    assert f"largest {predicted:+.2f} % at θ_o = " in title, title
    assert title in page.text_content("#data-largest")
    assert "θ_o = 0°" in title or "θ_o = -0°" in title
    assert not [p for p in page_log.problems() if "/datasets" in p], page_log.problems()


SLICE_LOOKS_JS = """() => {
  const div = document.getElementById('plot-slice'), box = (n) => n.getBoundingClientRect();
  const meet = (a, b) => a.left < b.right - 1 && b.left < a.right - 1 && a.top < b.bottom - 1 && b.top < a.bottom - 1;
  const yt = div.querySelector('.g-ytitle text'), others = [...div.querySelectorAll('.annotation-text, .cbtitle text, .g-gtitle text, .g-xtitle text')];
  const ticks = [...div.querySelectorAll('.colorbar .cbaxis text')].map(box);
  let tickOverlaps = 0;
  for (let i = 0; i < ticks.length; i++) for (let j = i + 1; j < ticks.length; j++) tickOverlaps += meet(ticks[i], ticks[j]);
  const y = yt && box(yt);
  return { figure: box(div).toJSON(), ytitle: y && y.toJSON(), ticks: ticks.map((b) => b.toJSON()), tickOverlaps,
           crossing: y ? others.filter((o) => meet(y, box(o))).map((o) => o.textContent) : [],
           bar: [...div.querySelectorAll('.cbtitle text')].map((t) => t.textContent).join(' ') }; }"""


def test_a_measured_file_opened_fitted_and_its_fit_loaded(page, page_log, tmp_path, shots):
    path = tmp_path / "coppery.binary"
    path.write_bytes(known.measured_style_bytes())
    page.goto("/?show=lobe,slice&theta_i_deg=30")
    wait_quiet(page, ids=("plot-lobe", "plot-slice"))
    page.set_input_files("#data-file", str(path))
    page.wait_for_function(OVERLAID, arg="plot-lobe", timeout=60_000)
    assert "merl" in page.text_content("#data-status")
    # the data's peak (its α = 0.06 lobe, far above the model's α = 0.3) is on the axis
    # drawn, not cut off at the model's top
    top, peak = page.evaluate("""async () => { const d = document.getElementById('plot-lobe');
        const { numbers } = await import('/static/js/chart/traces.js');     // a typed array sent as {dtype, bdata}
        const r = d.data.filter((t) => t.name && t.name.startsWith('data')).flatMap((t) => Array.from(numbers(t.r)))
          .filter(Number.isFinite);
        return [d.layout.polar.radialaxis.range[1], Math.max(...r)]; }""")
    assert peak > 0.1 and top >= peak, (top, peak)
    page.select_option("#data-channel", "r")
    page.click("#data-fit")
    page.wait_for_selector("#data-fit-use", timeout=60_000)
    result = page.text_content("#data-fit-result")
    assert "alpha = " in result and "residual" in result
    page.click("#data-fit-use")                      # the fitted model into the controls
    page.wait_for_function(OVERLAID, arg="plot-lobe", timeout=60_000)
    page.wait_for_function(OVERLAID, arg="plot-slice", timeout=60_000)
    fitted_alpha = page.evaluate("() => window.__brdf.state.alpha")
    assert 0.07 < fitted_alpha < 0.1              # one GGX lobe through the two (0.06, 0.3)
    page.wait_for_function("() => window.__brdf.pending() === 0")
    page.screenshot(path=str(shots / "screenshot-data.png"), full_page=False)
    assert "data (r)" in plot(page, "lobe")["names"]
    # the data's slice as a person reads it (issue 34): its y title inside the figure and
    # clear of every other text, the colour bar saying it is the data, its labels apart
    looks = page.evaluate(SLICE_LOOKS_JS)
    assert looks["ytitle"] and looks["ytitle"]["top"] >= looks["figure"]["top"] - 1, looks
    assert looks["crossing"] == [], looks
    assert "data (r)" in looks["bar"], looks
    assert len(looks["ticks"]) >= 2 and looks["tickOverlaps"] == 0, looks
    assert not [p for p in page_log.problems() if "/datasets" in p or "/fit" in p], page_log.problems()


def conductor_bytes() -> bytes:
    """A MERL file of GGX α = 0.2 with a conductor's Fresnel η = 0.5, κ = 2.5 and kd = 0.05,
    the same in each channel."""
    from app.datasets import merl, tabulate
    from app.model import make_spec
    brdf = make_spec(**CONDUCTOR).brdf()
    return merl.write(tabulate.merl_table([brdf] * 3))


CONDUCTOR = {"ndf": "ggx", "alpha": 0.2, "fresnel": "conductor", "ior": 0.5, "k": 2.5, "kd": 0.05}


def test_a_channel_change_replaces_the_data_label(page, page_log, tmp_path):
    path = tmp_path / "coppery.binary"
    path.write_bytes(known.measured_style_bytes())
    page.goto("/?show=lobe,ndf,g1&theta_i_deg=30")
    wait_quiet(page, ids=("plot-lobe", "plot-ndf", "plot-g1"))
    page.set_input_files("#data-file", str(path))
    page.wait_for_function(OVERLAID, arg="plot-lobe", timeout=60_000)
    labels = page.locator("#plot-lobe .chart-note")
    expect(labels).to_have_text(["data (luminance)"])
    page.select_option("#data-channel", "r")
    page.wait_for_function("() => [...document.querySelectorAll('#plot-lobe .chart-legend-text')]"
                           ".some((t) => t.textContent === 'data (r)')", timeout=60_000)
    expect(labels).to_have_text(["data (r)"])           # the luminance's label is gone
    legend = page.locator("#plot-lobe .chart-legend-text").all_text_contents()
    assert "data (luminance)" not in legend
    # a MERL table holds BRDF values: the term views (D, G1) are not asked to overlay it
    # (each such request was a 422 in the console)
    asked = [u for u in page_log.requests if "/datasets/" in u and "/figures/" in u]
    assert asked and not [u for u in asked if "/figures/ndf" in u or "/figures/g1" in u], asked
    assert not [p for p in page_log.problems() if "/datasets" in p], page_log.problems()


def test_a_conductor_fit_frees_eta_and_kappa_and_says_what_it_held(page, page_log, tmp_path):
    path = tmp_path / "conductor.binary"
    path.write_bytes(conductor_bytes())
    fits = []
    page.on("request", lambda r: fits.append(json.loads(r.post_data)) if r.url.endswith("/api/v1/fit") else None)
    page.goto("/?show=lobe&fresnel=conductor")
    wait_quiet(page, ids=("plot-lobe",))
    page.set_input_files("#data-file", str(path))
    page.wait_for_function(OVERLAID, arg="plot-lobe", timeout=60_000)
    expect(page.locator("#data-fit")).to_have_text("Fit α, k_d, η, κ")
    page.click("#data-fit")
    page.wait_for_selector("#data-fit-use", timeout=60_000)
    assert set(fits[-1]["free"]) == {"alpha", "kd", "ior", "k"}
    fitted = dict(re.findall(r"(\w+) = ([0-9.e+-]+) ±", page.text_content("#data-fit-params")))
    for name in ("alpha", "kd", "ior", "k"):      # the parameters the file was made with
        assert float(fitted[name]) == pytest.approx(CONDUCTOR[name], rel=1e-3), name
    held = page.text_content("#data-fit-held")
    assert "ndf=ggx" in held and "fresnel=conductor" in held and "ior" not in held
    assert not [p for p in page_log.problems() if "/datasets" in p or "/fit" in p], page_log.problems()
