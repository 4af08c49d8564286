"""The Content-Security-Policy (app/api/http/security.py) in a real Chromium, as the app
serves it: the page, the gallery and an embed of each kind of drawing — curves on the
chart, WebGL 3-D, a heatmap, an image — render with no violation, and the policy is really
enforced (an inline script is blocked).

Every other embed is drawn under a stricter policy than the app's (no script hashes, no
worker or font sources of its own) by tests/e2e/test_exports.py's
test_every_view_embeds_without_errors, which fails on any violation: what passes there
passes under the app's policy, so loading each embed here again would test nothing new."""
from __future__ import annotations

import pytest

from app.views import VIEWS

pytestmark = pytest.mark.e2e

CATCH = """
window.__csp = [];
document.addEventListener('securitypolicyviolation',
  e => window.__csp.push(e.violatedDirective + ' ' + e.blockedURI + ' ' + (e.sample || '')));
"""
#: an embed per kind of drawing: the chart (lobe), WebGL 3-D (lobe3d), a heatmap (slice),
#: an image (sphere)
EMBEDS = ("lobe", "lobe3d", "slice", "sphere")
PAGES = ["/", "/gallery"] + [f"/embed/{kind}" for kind in EMBEDS]


def test_the_embeds_here_are_views():
    assert set(EMBEDS) <= set(VIEWS)


@pytest.mark.parametrize("path", PAGES)
def test_pages_render_without_csp_violations(page, page_log, live_server, path):
    page.add_init_script(CATCH)
    page.goto(live_server + path)
    page.wait_for_load_state("networkidle")
    # a selector, not a predicate string: Playwright polls a string by eval, which this
    # page's CSP refuses whenever the plot is not drawn by the first check
    page.wait_for_selector(".js-plotly-plot .main-svg, .plot.chart canvas", state="attached", timeout=20_000)
    assert page.evaluate("window.__csp") == []
    assert not [m for m in page_log.console_errors if "Content Security Policy" in m]


def test_docs_render_offline_without_csp_violations(page, page_log, live_server):
    """Swagger UI at /docs draws every operation from same-origin files only (page_log
    fails the test on any request to another origin)."""
    page.add_init_script(CATCH)
    page.goto(live_server + "/docs")
    page.wait_for_load_state("networkidle")
    # a selector, not a predicate string: Playwright polls a string by eval, which the
    # page's CSP refuses when Swagger UI has not drawn at the first check (a loaded machine)
    page.locator(".opblock").nth(10).wait_for(timeout=20_000)
    assert page.evaluate("window.__csp") == []
    assert page_log.problems() == []


def test_policy_is_enforced(page, live_server):
    """Without this the test above would pass with no policy at all."""
    page.add_init_script(CATCH)
    page.goto(live_server + "/embed/ndf")
    page.wait_for_load_state("networkidle")
    # (eval cannot be probed from here: Playwright's own evaluation is exempt from CSP)
    page.evaluate("""() => { const s = document.createElement('script');
                             s.textContent = 'window.__ran = true'; document.body.appendChild(s); }""")
    assert page.evaluate("window.__ran === undefined")
    assert any("script-src" in v for v in page.evaluate("window.__csp"))
