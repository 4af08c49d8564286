"""A real server with two workers (issue 36): an id uploaded to one is served by both, 100
of 100 GETs on fresh connections, a delete is seen by both, and after a restart the id
still answers 200 and the deleted one 410 with the reason.

tests/datasets/test_api.py checks the same with two applications in one process; here the
workers are uvicorn's own processes sharing one listening socket, each with its own heavy
pool, as `brdf-explorer serve --workers 2` runs them (102 of 200 GETs answered 404 when a
data set lived in the worker that received it)."""
from __future__ import annotations

import json
import time
import urllib.error
import urllib.request
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

from tests.live import running_server

from .conftest import CSV

#: seconds an upload may be retried while the workers' heavy pools start (each answers
#: 503 with Retry-After until its process has imported the application)
START_SECONDS = 90.0


def _request(url: str, method: str = "GET", body: bytes | None = None,
             headers: dict | None = None) -> tuple[int, dict]:
    """(status, JSON body) of one request on a new connection (urllib opens one a call)."""
    req = urllib.request.Request(url, data=body, method=method, headers=headers or {})
    try:
        with urllib.request.urlopen(req, timeout=30) as res:
            return res.status, json.loads(res.read() or b"null")
    except urllib.error.HTTPError as err:
        return err.code, json.loads(err.read() or b"null")


def _upload(url: str, csv: bytes) -> dict:
    """POST ``csv``, retried on a 503 (Retry-After) while the heavy pools start."""
    give_up = time.monotonic() + START_SECONDS
    while True:
        status, body = _request(f"{url}/api/v1/datasets", "POST", csv, {"content-type": "text/csv"})
        if status != 503 or time.monotonic() > give_up:
            assert status == 201, (status, body)
            return body
        time.sleep(1.0)


def _workers(pid: int) -> int:
    """Child processes of uvicorn's supervisor (its workers)."""
    return sum(len(Path(task, "children").read_text().split())
               for task in Path(f"/proc/{pid}/task").iterdir())


def _gets(url: str, n: int = 100) -> list[tuple[int, dict]]:
    with ThreadPoolExecutor(max_workers=4) as pool:      # several connections at once
        return list(pool.map(lambda _: _request(url), range(n)))


def test_two_workers_and_a_restart_serve_an_upload(tmp_path):
    env = {"BRDF_CACHE_DIR": str(tmp_path)}
    with running_server(("--workers", "2"), env=env, seconds=120) as (url, proc):
        assert _workers(proc.pid) >= 2
        kept, deleted = _upload(url, CSV), _upload(url, CSV.replace(b"1.5", b"1.25"))
        answers = _gets(f"{url}/api/v1/datasets/{kept['id']}")
        assert [status for status, _ in answers] == [200] * 100, answers
        assert all(b["summary"] == kept["summary"] for _, b in answers)
        status, _ = _request(f"{url}/api/v1/datasets/{deleted['id']}?token={deleted['token']}", "DELETE")
        assert status == 204
        gone = _gets(f"{url}/api/v1/datasets/{deleted['id']}", 20)      # on both workers
        assert all(s == 410 and "deleted" in b["detail"][0]["msg"] for s, b in gone), gone
    with running_server(env=env, seconds=120) as (url, proc):           # the restart
        status, body = _request(f"{url}/api/v1/datasets/{kept['id']}")
        assert status == 200 and body["summary"] == kept["summary"], (status, body)
        status, body = _request(f"{url}/api/v1/datasets/{deleted['id']}")
        assert status == 410 and "deleted" in body["detail"][0]["msg"], (status, body)
