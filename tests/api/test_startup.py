"""``brdf-explorer serve`` accepts at once (app/api/startup.py): uvicorn serves ``Starting``,
which imports the application in a background thread, answers the page's own files
meanwhile through the same HTTP layers, and holds every other request until the
application has started. The page's files must be the same bytes and headers either way."""
from __future__ import annotations

import sys
import threading
import time
import warnings

import pytest

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.api import startup

PAGE = ["/", "/favicon.ico", "/static/vendor/plotly.min.js", "/static/style.css",
        "/static/early.js", "/static/js/app/main.js"]
VOLATILE = {"date"}


@pytest.fixture
def slow_target(tmp_path, monkeypatch):
    """A module whose import waits for ``release``: the application, still importing."""
    release, started = threading.Event(), []
    (tmp_path / "slow_target_app.py").write_text(
        "import builtins\n"
        "builtins.__slow_release__.wait(30)\n"
        "from app.main import create_app\n"
        "app = create_app()\n"
        "builtins.__slow_started__.append(1)\n")
    import builtins
    monkeypatch.setattr(builtins, "__slow_release__", release, raising=False)
    monkeypatch.setattr(builtins, "__slow_started__", started, raising=False)
    monkeypatch.syspath_prepend(str(tmp_path))
    yield release, started
    release.set()
    sys.modules.pop("slow_target_app", None)


def _shown(response) -> tuple:
    headers = sorted((k, v) for k, v in response.headers.items() if k not in VOLATILE)
    return response.status_code, headers, response.content


def test_the_page_is_served_while_the_application_imports_and_the_api_waits(slow_target):
    release, started = slow_target
    starting = startup.Starting("slow_target_app:app", stop=lambda: None)
    with TestClient(starting) as client:
        early = {path: client.get(path) for path in PAGE}
        assert all(r.status_code == 200 for r in early.values())
        assert not started and starting.app is None          # still importing
        answers = []
        waiting = threading.Thread(target=lambda: answers.append(client.get("/api/v1/health")))
        waiting.start()
        time.sleep(0.3)
        assert answers == []                                  # held until the app is ready
        release.set()
        waiting.join(60)
        assert answers and answers[0].status_code == 200 and starting.app is not None
        # the same bytes and headers as the application gives, gzip or not, and its 304s
        for path in PAGE:
            assert _shown(client.get(path)) == _shown(early[path]), path
            etag = early[path].headers["etag"]
            assert client.get(path, headers={"if-none-match": etag}).status_code == 304
        plain = {"accept-encoding": "identity"}
        assert "content-encoding" not in client.get("/static/vendor/plotly.min.js", headers=plain).headers


def test_before_the_application_only_existing_page_files_are_answered(slow_target):
    release, _ = slow_target
    starting = startup.Starting("slow_target_app:app", stop=lambda: None)
    with TestClient(starting):
        serves = starting._files[0]

        def scope(path, method="GET", qs=b""):
            return {"type": "http", "method": method, "path": path, "query_string": qs}
        assert serves(scope("/")) and serves(scope("/static/js/app/main.js"))
        assert not serves(scope("/static/no-such-file.js"))           # the app's own 404
        assert not serves(scope("/static/../app/main.py"))
        assert not serves(scope("/static/js"))                        # a directory
        assert not serves(scope("/static/vendor/swagger-ui/swagger-ui.css"))
        assert not serves(scope("/", method="POST")) and not serves(scope("/", qs=b"a=1"))
        assert not serves(scope("/api/v1/health")) and not serves(scope("/docs"))
        release.set()


def test_an_application_that_fails_to_start_stops_the_server(tmp_path, monkeypatch):
    from app import server
    monkeypatch.setattr(server, "failed", None)
    (tmp_path / "broken_target_app.py").write_text("raise RuntimeError('no such thing')\n")
    monkeypatch.syspath_prepend(str(tmp_path))
    stopped = []
    starting = startup.Starting("broken_target_app:app", stop=lambda: stopped.append(1))
    with TestClient(starting) as client:
        r = client.get("/api/v1/health")
        assert r.status_code == 503 and "failed to start" in r.json()["detail"]
    assert stopped == [1] and "no such thing" in starting.failed
    assert "no such thing" in server.failed          # brdf-explorer serve exits with 1
    sys.modules.pop("broken_target_app", None)
