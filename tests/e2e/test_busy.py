"""A busy server (503 with Retry-After: a table being built, a time budget spent on a
loaded machine) is waited for, not shown as an error: the panel or the embed says it
waits, asks again when the server said, and draws (static/js/net/scheduler.js). Only when
the server stays busy is its message shown as the error."""
from __future__ import annotations

import json
import time

import pytest

from test_page import wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e

BUSY = {"detail": [{"loc": ["query", "table"], "msg": "the test's table is being built: retry",
                    "type": "busy"}]}
# what a status said, recorded in the page as it changes (a poll from the test can miss
# a status shown for less than the poll's period)
RECORD_STATUS_JS = """(selector) => document.addEventListener('DOMContentLoaded', () => {
    window.__statuses = [];
    new MutationObserver(() => {
      const s = document.querySelector(selector);
      if (s && s.textContent && s.textContent !== window.__statuses.at(-1)) window.__statuses.push(s.textContent);
    }).observe(document.body, { subtree: true, attributes: true, childList: true, characterData: true });
  })"""


def record_status(page, selector):
    page.add_init_script(f"({RECORD_STATUS_JS})({json.dumps(selector)})")


def test_a_busy_panel_says_so_and_asks_again_when_told(page, page_log):
    asked = []                     # when g1 was asked, and how it was answered

    def batch(route):
        sent = json.loads(route.request.post_data)["requests"]
        answer = route.fetch().json()
        for u, r in zip(sent, answer["responses"]):
            if u.startswith("/api/v1/figures/g1?"):
                busy = not asked
                asked.append((time.monotonic(), busy))
                if busy:
                    r.update(status=503, cache="no-store", retry_after=1, body=BUSY)
        route.fulfill(status=200, content_type="application/json", body=json.dumps(answer))

    def g1(route):
        asked.append((time.monotonic(), False))
        route.continue_()
    page.route("**/api/v1/batch", batch)
    page.route("**/api/v1/figures/g1?*", g1)
    record_status(page, '[data-panel="g1"] .panel-status')
    page.goto("/")
    wait_quiet(page)
    assert [busy for _, busy in asked] == [True, False]          # asked once more, and only once
    assert asked[1][0] - asked[0][0] >= 0.9                       # when the server said
    said = page.evaluate("() => window.__statuses")   # "loading…" may come first on a slow machine
    assert any("being built" in t and "asking again in 1 s" in t for t in said), said
    status = page.locator('[data-panel="g1"] .panel-status')
    assert status.inner_text() == ""                              # drawn: nothing to say
    assert page.evaluate("() => window.__brdf.panels().find((p) => p.name === 'g1').current")
    assert page_log.problems() == []


def test_an_embed_waits_for_a_busy_server(page, page_log):
    asked = []

    def ndf(route):
        asked.append(time.monotonic())
        if len(asked) == 1:
            route.fulfill(status=503, content_type="application/json", body=json.dumps(BUSY),
                          headers={"Retry-After": "1", "Cache-Control": "no-store"})
        else:
            route.continue_()
    page.route("**/api/v1/figures/ndf?*", ndf)
    record_status(page, "#status")
    page.goto("/embed/ndf?alpha=0.2")
    page.wait_for_function("() => window.__embed && window.__embed.pending() === 0 && window.__embed.drawn()",
                           timeout=20_000)
    assert len(asked) == 2 and asked[1] - asked[0] >= 0.9
    assert any("asking again in 1 s" in s for s in page.evaluate("() => window.__statuses"))
    assert page.inner_text("#status") == ""
    assert page_log.page_errors == []
    # the browser reports the 503 it was given in its console; nothing else
    assert all("503" in e for e in page_log.console_errors)


def test_a_server_that_stays_busy_is_shown_as_the_error(page, page_log):
    asked = []

    def ndf(route):
        asked.append(time.monotonic())
        route.fulfill(status=503, content_type="application/json", body=json.dumps(BUSY),
                      headers={"Retry-After": "0", "Cache-Control": "no-store"})
    page.route("**/api/v1/figures/ndf?*", ndf)
    page.goto("/embed/ndf?alpha=0.2")
    page.wait_for_function("() => window.__embed && window.__embed.pending() === 0", timeout=20_000)
    assert "the test's table is being built" in page.inner_text("#status")
    assert not page.evaluate("() => window.__embed.drawn()")
    assert len(asked) == 9              # the first answer and MAX_BUSY_TRIES = 8 more
    assert page_log.page_errors == []
