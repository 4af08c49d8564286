"""The identity checks on a desktop (1400 × 900): the whole table is in view, its last
row too (issue 34: it was cut at row 7, the panel one grid row high for a table of 11)."""
from __future__ import annotations

import pytest

from test_page import wait_quiet   # tests/e2e is not a package

pytestmark = pytest.mark.e2e


def test_every_check_is_in_view_on_a_desktop(page, page_log):
    page.set_viewport_size({"width": 1400, "height": 900})
    page.goto("/?show=checks")
    wait_quiet(page, ["plot-checks"], timeout=60_000)
    plot = page.locator("#plot-checks").bounding_box()
    # the table's rows as drawn: the first column's cells (the identities' numbers)
    cells = page.locator("#plot-checks .y-column").first.locator(".cell-text").all()
    shown = [c for c in cells if c.text_content().strip()]
    assert len(shown) >= 8, [c.text_content() for c in shown]
    for c in shown:
        box = c.bounding_box()
        assert box["y"] >= plot["y"] and box["y"] + box["height"] <= plot["y"] + plot["height"], c.text_content()
    assert page_log.problems() == []
