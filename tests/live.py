"""The one way tests and benchmarks start a real server: the app in its own uvicorn
process on a free port of 127.0.0.1, waited for until it answers, stopped by its pid.

Here rather than in app/: it is a development tool, not part of what the wheel ships,
and bench/ imports it (bench/common.py puts the checkout on sys.path) as the tests do."""
from __future__ import annotations

import contextlib
import os
import socket
import subprocess
import sys
import tempfile
import time
import urllib.request
from pathlib import Path

ROOT = Path(__file__).resolve().parents[1]
#: `brdf-explorer serve`'s default port, never taken here (a developer's server may be on it)
DEFAULT_PORT = 8000
#: how often a starting server is asked whether it answers: a start takes 1-12 s, and a
#: second's poll left each test waiting half a second on average past it
POLL_SECONDS = 0.2


def free_port() -> int:
    """A free TCP port on 127.0.0.1 (never DEFAULT_PORT)."""
    while True:
        with socket.socket() as s:
            s.bind(("127.0.0.1", 0))
            port = s.getsockname()[1]
        if port != DEFAULT_PORT:
            return port


def healthy(url: str) -> bool:
    """Whether ``url``'s /api/v1/health answers 200 now."""
    try:
        with urllib.request.urlopen(f"{url}/api/v1/health", timeout=2) as res:
            return res.status == 200
    except OSError:
        return False


def wait_until_up(url: str, proc: subprocess.Popen, seconds: float) -> None:
    """Poll ``url`` until it answers; fail with the server's stderr if it exits first."""
    deadline = time.monotonic() + seconds
    while True:
        try:
            urllib.request.urlopen(url, timeout=30)
            return
        except OSError:
            assert proc.poll() is None, proc.stderr.read().decode() if proc.stderr else "server exited"
            assert time.monotonic() < deadline, f"server did not answer {url} within {seconds} s"
            time.sleep(POLL_SECONDS)


def stop(proc: subprocess.Popen, seconds: float = 30) -> None:
    """SIGTERM (uvicorn's graceful shutdown), SIGKILL after ``seconds``: this process only."""
    proc.terminate()
    try:
        proc.wait(timeout=seconds)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()


@contextlib.contextmanager
def running_server(args: tuple[str, ...] = (), env: dict | None = None, log_path: Path | None = None,
                   seconds: float = 60.0, attempts: int = 3):
    """``uvicorn --factory app.main:create_app`` (plus ``args``: ``--workers 2``...) with
    ``env`` added to the environment; yields (base URL, process) once /api/v1/health
    answers (a clean clone compiles the fast path first, ~12 s), and stops it on the way
    out. A port taken meanwhile is tried again with another; the log goes to ``log_path``."""
    log_path = log_path or Path(tempfile.gettempdir()) / f"brdf-server-{os.getpid()}.log"
    for _attempt in range(attempts):
        url = f"http://127.0.0.1:{(port := free_port())}"
        with open(log_path, "ab") as log:
            proc = subprocess.Popen(
                [sys.executable, "-m", "uvicorn", "--factory", "app.main:create_app",
                 "--host", "127.0.0.1", "--port", str(port), "--log-level", "warning", *args],
                cwd=ROOT, stdout=log, stderr=subprocess.STDOUT,
                env={**os.environ, "PYTHONPATH": str(ROOT), **(env or {})})
        deadline = time.monotonic() + seconds
        while proc.poll() is None and time.monotonic() < deadline and not healthy(url):
            time.sleep(0.1)
        if proc.poll() is None and healthy(url):
            break
        stop(proc, 10)
    else:
        raise RuntimeError(f"uvicorn did not start; see {log_path}:\n{log_path.read_text()[-4000:]}")
    try:
        yield url, proc
    finally:
        stop(proc, 10)
