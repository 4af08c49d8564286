"""Issue 31's extension contract on the page: a model family written as one package in a
temporary directory (tests/toy_family.py: Lambert + Phong, two parameters) and named by
BRDF_MODEL_DIRS appears in the page's model menu with its two sliders, its values go to
the panels that draw it and into the link, and a panel that does not draw it says so —
with no file of static/ or app/ edited (the page reads the families from /api/v1/models).
"""
from __future__ import annotations

import sys
import time
from pathlib import Path
from urllib.parse import parse_qs, urlparse

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2]))
from tests.live import running_server                   # noqa: E402
from tests.toy_family import NAME, write_family          # noqa: E402
from test_page import move_slider                        # noqa: E402  (tests/e2e is not a package)

pytestmark = pytest.mark.e2e


@pytest.fixture(scope="module")
def toy_server(tmp_path_factory):
    with running_server(env={"BRDF_MODEL_DIRS": str(write_family(tmp_path_factory.mktemp("families")))}) as (url, _):
        yield url


def _figure_requests(sent: list[str], view: str) -> list[dict[str, str]]:
    return [{k: v[-1] for k, v in parse_qs(urlparse(u).query).items()}
            for u in sent if urlparse(u).path == f"/api/v1/figures/{view}"]


def _until(page, predicate, seconds: float = 60.0):
    """Wait, letting the page's events in (Playwright delivers them while it waits)."""
    deadline = time.monotonic() + seconds
    while not predicate():
        assert time.monotonic() < deadline, "timed out"
        page.wait_for_timeout(200)


def test_the_toy_family_is_in_the_menu_with_its_sliders(page, toy_server):
    sent: list[str] = []
    errors: list[str] = []
    page.on("request", lambda r: sent.append(r.url))
    page.on("pageerror", lambda e: errors.append(str(e)))
    page.goto(f"{toy_server}/?show=lobe,g1")
    page.wait_for_selector(f"#model option[value={NAME}]", state="attached", timeout=60_000)
    assert "Lambert + Phong" in page.inner_text(f"#model option[value={NAME}]")
    assert not page.is_visible(f"#{NAME}-rho-d")          # the default family's controls first
    page.select_option("#model", NAME)
    for name in ("rho-d", "shininess"):
        assert page.is_visible(f"#{NAME}-{name}") and page.is_visible(f"#{NAME}-{name}-slider")
    assert not page.is_visible("#ndf") and not page.is_visible("#alpha")
    move_slider(page, f"{NAME}-rho-d-slider", 0.25)
    _until(page, lambda: any(q.get("model") == NAME and q.get("rho_d") == "0.25"
                       for q in _figure_requests(sent, "lobe")))
    lobe = [q for q in _figure_requests(sent, "lobe") if q.get("model") == NAME][-1]
    assert "alpha" not in lobe and "ndf" not in lobe      # only the family's own parameters
    # the link carries the family and its value; the G1 panel (not drawn for it) says so
    _until(page, lambda: "rho_d=0.25" in page.url)
    assert parse_qs(urlparse(page.url).query)["model"] == [NAME]
    note = page.locator("#note-g1")
    assert note.is_visible() and "toy family draws" in note.inner_text()
    assert not [q for q in _figure_requests(sent, "g1") if q.get("model") == NAME]
    # the link restores the family's controls
    page.goto(page.url)
    page.wait_for_selector(f"#{NAME}-rho-d", state="visible", timeout=60_000)
    assert page.input_value("#model") == NAME and page.input_value(f"#{NAME}-rho-d") == "0.25"
    assert errors == []
