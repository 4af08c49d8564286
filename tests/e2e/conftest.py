"""Browser tests: the real app in a uvicorn process, Debian's Chromium driven by Playwright.

Playwright's own browser download is not used (it cannot be fetched here); the tests
launch the system Chromium at $BRDF_CHROMIUM (default /usr/bin/chromium); without it
the run stops with a message saying what to install.
"""
from __future__ import annotations

import json
import os
import shutil
from dataclasses import dataclass, field
from pathlib import Path
from urllib.parse import urlparse

import pytest

from tests.budget import TEST_MAX_SECONDS
from tests.live import running_server

CHROMIUM = os.environ.get("BRDF_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = [
    "--no-sandbox",
    "--disable-gpu",
    "--disable-background-networking",
    "--disable-component-update",
    "--disable-sync",
    "--no-first-run",
]
VIEWPORT = {"width": 1280, "height": 800}
ROOT = Path(__file__).resolve().parents[2]


def _have_chromium() -> bool:
    return os.path.exists(CHROMIUM) or shutil.which(CHROMIUM) is not None


def pytest_collection_modifyitems(config, items):
    # No skip: a browser test that did not run must not look like one that passed.
    # The README's test command installs Chromium; without it these tests fail loudly.
    if any("e2e" in item.keywords for item in items) and not _have_chromium():
        raise pytest.UsageError(
            f"no Chromium at {CHROMIUM}: install it (apt-get install -y chromium) "
            "or set BRDF_CHROMIUM; deselect browser tests with -m 'not e2e'")


@pytest.fixture(scope="session")
def browser_type_launch_args(browser_type_launch_args):
    return {**browser_type_launch_args, "executable_path": CHROMIUM, "args": CHROMIUM_ARGS}


@pytest.fixture(scope="session")
def browser_context_args(browser_context_args):
    return {**browser_context_args, "viewport": VIEWPORT}


@pytest.fixture(scope="session")
def _profile(playwright, browser_type_launch_args, browser_context_args, tmp_path_factory):
    """One browser profile on disk for the session's pages. Chromium keeps scripts'
    compiled code only in a profile on disk: in one, plotly.js's evaluation at each page
    load falls from ~0.7 s to ~0.06 s from the third load on (a fresh in-memory context
    for each test paid it every time: most of a browser test's fixed cost, on a machine
    the suite keeps busy)."""
    ctx = playwright.chromium.launch_persistent_context(
        str(tmp_path_factory.mktemp("chromium-profile")), **browser_type_launch_args, **browser_context_args)
    yield ctx
    ctx.close()


@pytest.fixture
def context(_profile):
    """The session's profile with nothing of the test before: its pages closed, no
    cookies, no permissions granted; the page keeps no other state (sessionStorage is a
    page's own, and nothing uses localStorage). The HTTP cache stays: the compiled
    scripts are kept with it."""
    yield _profile
    for p in list(_profile.pages):
        p.close()
    _profile.clear_cookies()
    _profile.clear_permissions()


@pytest.fixture(scope="session")
def live_server(tmp_path_factory):
    """The real app in its own process (tests/live.py), so that timings are not skewed by
    sharing the test process's interpreter."""
    log_path = tmp_path_factory.mktemp("server") / "uvicorn.log"
    with running_server(env={"BRDF_MAX_SECONDS": str(TEST_MAX_SECONDS)}, log_path=log_path) as (url, _):
        yield url


@pytest.fixture(scope="session")
def base_url(live_server):
    """Lets tests write page.goto("/?alpha=0.2")."""
    return live_server


@dataclass
class PageLog:
    """What went wrong in the page: console errors, exceptions, failed or bad requests,
    and any request that left the app's own origin."""
    origin: str
    console_errors: list[str] = field(default_factory=list)
    page_errors: list[str] = field(default_factory=list)
    failed_requests: list[str] = field(default_factory=list)
    bad_responses: list[str] = field(default_factory=list)
    external_requests: list[str] = field(default_factory=list)
    requests: list[str] = field(default_factory=list)
    #: main-frame navigations so far, and the requests that failed net::ERR_ABORTED with the
    #: navigation count when they were sent
    navigations: int = 0
    aborted: list[tuple[int, str]] = field(default_factory=list)

    def problems(self) -> list[str]:
        return [*self.console_errors, *self.page_errors, *self.failed_requests, *self.cut_by_the_page(),
                *self.bad_responses, *(f"external request: {u}" for u in self.external_requests)]

    def cut_by_the_page(self) -> list[str]:
        """Aborted requests, but for those of a document the test navigated away from: a
        browser aborts what a page it leaves still fetches (a refining sphere, say), and
        that is the test's doing, not the page's."""
        return [f"request failed: {url} (net::ERR_ABORTED)"
                for sent_at, url in self.aborted if sent_at == self.navigations]


@pytest.fixture
def page_log(page, live_server):
    log = PageLog(live_server)

    def on_console(msg):
        if msg.type == "error":
            log.console_errors.append(f"console {msg.type}: {msg.text}")

    def on_request(req):
        sent_at[req] = log.navigations
        log.requests.append(req.url)
        # the panels' figure GETs of one change travel in one POST /api/v1/batch
        # (static/js/net/batch.js): each is logged as the GET it stands for
        if req.method == "POST" and urlparse(req.url).path == "/api/v1/batch":
            log.requests.extend(live_server + u for u in json.loads(req.post_data or "{}").get("requests", []))
        if not (req.url.startswith(live_server) or req.url.startswith(("data:", "blob:"))):
            log.external_requests.append(req.url)

    def on_response(res):
        if res.status >= 400:
            log.bad_responses.append(f"HTTP {res.status}: {res.url}")

    page.on("console", on_console)
    page.on("pageerror", lambda err: log.page_errors.append(f"page error: {err}"))
    def on_failed(req):
        if req.failure == "net::ERR_ABORTED":
            log.aborted.append((sent_at.get(req, log.navigations), req.url))
        else:
            log.failed_requests.append(f"request failed: {req.url} ({req.failure})")

    def on_navigated(frame):
        if frame == page.main_frame:
            log.navigations += 1

    sent_at: dict = {}
    page.on("requestfailed", on_failed)
    page.on("framenavigated", on_navigated)
    page.on("request", on_request)
    page.on("response", on_response)
    return log


@pytest.fixture(scope="session")
def shots(tmp_path_factory) -> Path:
    """Where the screenshots the tests take go: a temporary directory, never the checkout.
    bench/screenshots.py points BRDF_SCREENSHOT_DIR at docs/ to refresh the README's images
    from the same tests."""
    chosen = os.environ.get("BRDF_SCREENSHOT_DIR")
    if chosen:
        Path(chosen).mkdir(parents=True, exist_ok=True)
        return Path(chosen)
    return tmp_path_factory.mktemp("screenshots")
