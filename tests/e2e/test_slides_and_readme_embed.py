"""Issue 11's embeds and exports where teachers put them: the README's own iframe snippet,
at the size it states, shows its legend and its export bar (the plot was sized before the
controls appeared, which pushed both out of the frame); a panel's SVG comes at slide
size, 1600 × 1000, from the server and from the browser's fallback alike (it came at the
panel's size, where legends sat on axis titles)."""
from __future__ import annotations

import json
import re
from pathlib import Path
from urllib.parse import urlparse

import pytest

from test_page import wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

ROOT = Path(__file__).resolve().parents[2]
EMBED_QUIET = "() => window.__embed && window.__embed.pending() === 0 && window.__embed.drawn()"


def readme_iframe() -> tuple[str, int, int]:
    """The src (path and query), width and height of the README's iframe snippet."""
    readme = (ROOT / "README.md").read_text(encoding="utf-8")
    (tag,) = re.findall(r"<iframe\s+src=[^>]*>", readme)
    src = urlparse(re.search(r'src="([^"]+)"', tag).group(1))
    width, height = (int(re.search(rf'{a}="(\d+)"', tag).group(1)) for a in ("width", "height"))
    return f"{src.path}?{src.query}", width, height


def inside(page, selector: str) -> bool:
    """Whether the element is drawn (non-empty box) wholly inside the viewport."""
    return page.evaluate("""(sel) => { const e = document.querySelector(sel);
        if (!e) return false;
        const r = e.getBoundingClientRect();
        return r.width > 0 && r.height > 0 && r.top >= -1 && r.left >= -1
            && r.bottom <= innerHeight + 1 && r.right <= innerWidth + 1; }""", selector)


def svg_size(text: str) -> tuple[float, float]:
    root = re.search(r"<svg\b[^>]*>", text).group(0)
    return tuple(float(re.search(rf'\b{a}="([\d.]+)', root).group(1)) for a in ("width", "height"))


def test_readme_iframe_snippet_shows_legend_and_export_bar(page, page_log):
    path, width, height = readme_iframe()
    assert "controls=1" in path
    page.set_viewport_size({"width": width, "height": height})      # the frame's own size
    # The controls are built from /models and /views; on a real network the figure can
    # land first. Hold those two until the plot is drawn, so the controls appear after it
    # (in that order the plot kept the whole frame and pushed the bar and legend out).
    held = []
    page.route(lambda url: urlparse(url).path in ("/api/v1/models", "/api/v1/views"),
               lambda route: held.append(route))
    page.goto(path)
    page.wait_for_function(EMBED_QUIET, timeout=30_000)
    assert held, "the controls' requests were not sent"
    for route in held:
        route.continue_()
    page.wait_for_function("() => document.querySelector('#embed-controls input')")
    page.wait_for_timeout(300)                      # the plot re-fits after the controls
    assert page.evaluate("() => document.documentElement.scrollHeight <= innerHeight + 1")
    for selector in ("#embed-bar", '#embed-bar button[data-format="svg"]',
                     '#embed-bar button[data-format="png"]', "#plot .legend"):
        assert inside(page, selector), selector
    drawn = page.evaluate("() => Number(document.querySelector('#plot svg.main-svg').getAttribute('height'))")
    box = page.locator("#plot").bounding_box()
    assert abs(drawn - box["height"]) <= 2          # drawn at the size left by the controls
    assert page_log.problems() == []


def download_ndf_svg(page, query: str, timeout_ms: int):
    """The NDF panel's SVG button, clicked on a 1400×900 page: the download."""
    page.set_viewport_size({"width": 1400, "height": 900})
    page.goto(f"/?{query}show=lobe,ndf")
    wait_quiet(page, ids=("plot-lobe", "plot-ndf"))
    with page.expect_download(timeout=timeout_ms) as dl:
        page.locator('[data-panel="ndf"] button[data-format="svg"]').click()
    return dl.value


def test_panel_svg_is_slide_sized_from_the_server(page, page_log):
    download = download_ndf_svg(page, "alpha=0.2&", 90_000)
    assert svg_size(Path(download.path()).read_text(encoding="utf-8")) == (1600, 1000)
    assert "alpha=0.2" in download.suggested_filename
    assert page_log.problems() == []


def test_panel_svg_is_slide_sized_when_the_browser_draws_it(page, page_log):
    """Without a renderer on the server (503) the page exports the drawn plot itself: at
    the same slide size, not the panel's."""
    body = json.dumps({"detail": "No Chromium found (simulated)"})
    page.route("**/api/v1/figures/ndf.svg?*",
               lambda r: r.fulfill(status=503, body=body, content_type="application/json"))
    download = download_ndf_svg(page, "", 30_000)
    assert svg_size(Path(download.path()).read_text(encoding="utf-8")) == (1600, 1000)
    assert page_log.page_errors == [] and all("503" in e for e in page_log.console_errors)


def test_comparison_heading_names_the_models_not_the_views_description(page, page_log, base_url):
    """Two pinned models on the D panel: the heading is the view's title and what is
    compared, not the API's description of the view ('D(θ_m) at azimuth φ, θ_m = 0..90°:
    2 models', the comparison figure's old title)."""
    page.goto("/?pin=ndf:beckmann,alpha:0.2&show=ndf,lobe")
    wait_quiet(page, ids=("plot-ndf", "plot-lobe"))
    text = page.locator('[data-panel="ndf"] h2').inner_text()
    assert "azimuth" not in text and "0..90" not in text, text
    title = next(v["title"] for v in page.request.get(f"{base_url}/api/v1/views").json() if v["name"] == "ndf")
    assert text.startswith(title) and "2 models" in text, text
    assert page_log.problems() == []


def test_panel_headings_keep_names_whole(page, page_log):
    """What the page draws (not only its richText helper): with names that hold
    underscores in the URL (height_direction_correlated, van_ginneken) no panel heading or
    toggle shows half a name as a subscript ('height<sub>correlated</sub>')."""
    page.goto("/?show=g2,lobe,ndf&g2=height_direction_correlated&lambda_phi=van_ginneken")
    wait_quiet(page, ids=("plot-g2", "plot-lobe", "plot-ndf"))
    subs = page.evaluate("""() => [...document.querySelectorAll('sub')]
        .filter((s) => !s.closest('.js-plotly-plot')).map((s) => s.textContent)""")
    assert all(len(s) <= 3 for s in subs), subs
    html = page.evaluate("() => [...document.querySelectorAll('.panel h2')].map((h) => h.innerHTML).join(' | ')")
    assert "<sub>correlated" not in html and "<sub>ginneken" not in html, html
    assert page_log.problems() == []
