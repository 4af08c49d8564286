"""An embed frames where teachers put it: a slide deck opened from disk (file:) and a
page of any other origin both show its plot."""
from __future__ import annotations

import functools
import http.server
import threading

import pytest

pytestmark = pytest.mark.e2e

def _deck(src: str) -> str:
    return ("<!doctype html><title>deck</title>"
            f'<iframe id="embed" src="{src}" width="640" height="440"></iframe>')


def _plot_in_frame(page, live_server: str) -> None:
    """The embed's frame (of the live server's origin) drew its curve. Locators only:
    the embed's policy allows no string evaluation, and bypassing it would also bypass
    the framing rule under test."""
    frame = None
    for _ in range(200):                       # the child frame navigates after the parent
        frame = next((f for f in page.frames if f.url.startswith(live_server + "/embed/")), None)
        if frame is not None:
            break
        page.wait_for_timeout(100)
    assert frame is not None, [f.url for f in page.frames]
    frame.locator(".js-plotly-plot .scatterlayer .trace").first.wait_for(state="attached",
                                                                         timeout=45_000)


def test_embed_renders_inside_a_file_page(page, live_server, tmp_path):
    deck = tmp_path / "slides.html"
    deck.write_text(_deck(f"{live_server}/embed/lobe?alpha=0.2&theta_i_deg=60"), encoding="utf-8")
    page.goto(deck.as_uri())
    _plot_in_frame(page, live_server)


@pytest.fixture
def other_origin(tmp_path):
    """A second server (another port: another origin) that serves tmp_path's files."""
    handler = functools.partial(http.server.SimpleHTTPRequestHandler, directory=str(tmp_path))
    server = http.server.ThreadingHTTPServer(("127.0.0.1", 0), handler)
    thread = threading.Thread(target=server.serve_forever, daemon=True)
    thread.start()
    yield tmp_path, f"http://127.0.0.1:{server.server_address[1]}"
    server.shutdown()
    server.server_close()


def test_embed_renders_inside_a_page_of_another_origin(page, live_server, other_origin):
    folder, origin = other_origin
    (folder / "slides.html").write_text(_deck(f"{live_server}/embed/lobe?alpha=0.2"),
                                        encoding="utf-8")
    page.goto(f"{origin}/slides.html")
    _plot_in_frame(page, live_server)
