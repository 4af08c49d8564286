"""SIGTERM while heavy requests run: `brdf-explorer serve` ends within its graceful
timeout (its default: BRDF_MAX_SECONDS + 1 s) whatever they are doing: an upload's
summary and an export in the heavy pool, a LUT check in a server thread. Before the pool
an upload's summary ran in a server thread for minutes and SIGTERM hung until SIGKILL
(issue 36); concurrent.futures' exit hook would join a running job the same way.

A small budget (BRDF_MAX_SECONDS=2: graceful 3 s) makes the bound bite quickly; the
real-size requests at the default limits are bench/worst_heavy.py's."""
from __future__ import annotations

import json
import os
import random
import signal
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request

from tests.live import ROOT, free_port, healthy

MAX_SECONDS = 2.0
#: serve's default graceful timeout for that budget (app/cli/serve.py)
GRACEFUL = MAX_SECONDS + 1.0
#: seconds from SIGTERM to the exit of the interpreter beyond the graceful timeout: the
#: lifespan's shutdown (the pool's workers killed and reaped) and the interpreter's own end
EXIT_SLACK = 1.5


def _csv(rows: int) -> bytes:
    rng = random.Random(7)
    lines = ["theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f"]
    lines += [f"{rng.uniform(0, 89):.3f},0,{rng.uniform(0, 89):.3f},{rng.uniform(0, 359):.3f},1"
              for _ in range(rows)]
    return ("\n".join(lines) + "\n").encode()


def _post(url: str, body: bytes | None, ctype: str | None, out: list) -> None:
    req = urllib.request.Request(url, data=body, method="POST" if body is not None else "GET",
                                 headers={"content-type": ctype} if ctype else {})
    try:
        with urllib.request.urlopen(req, timeout=30) as res:
            out.append(res.status)
    except urllib.error.HTTPError as e:
        out.append(e.code)
    except OSError as e:
        out.append(type(e).__name__)


def test_sigterm_during_heavy_requests_ends_within_the_graceful_timeout(tmp_path):
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    env = {**os.environ, "PYTHONPATH": str(ROOT), "BRDF_MAX_SECONDS": str(MAX_SECONDS),
           "BRDF_CACHE_DIR": str(tmp_path)}
    proc = subprocess.Popen([sys.executable, "-m", "app.cli", "serve", "--host", "127.0.0.1",
                             "--port", str(port)], cwd=ROOT, env=env,
                            stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL)
    try:
        deadline = time.monotonic() + 60
        while not healthy(base):
            assert proc.poll() is None and time.monotonic() < deadline, "the server did not start"
            time.sleep(0.1)
        lut = json.dumps({"values": [[[random.random(), random.random()] for _ in range(64)]
                                     for _ in range(64)]}).encode()
        requests = [(f"{base}/api/v1/datasets", _csv(150_000), "text/csv"),
                    (f"{base}/api/v1/export/model.csv?n_theta=91&n_phi=40&masking=smith_numeric", None, None),
                    (f"{base}/api/v1/lut/check?kind=split_sum", lut, "application/json")]
        answers: list = []
        threads = [threading.Thread(target=_post, args=(*r, answers), daemon=True) for r in requests]
        for t in threads:
            t.start()
        time.sleep(1.0)                   # the bodies sent, the work under way
        t0 = time.perf_counter()
        proc.send_signal(signal.SIGTERM)
        try:
            proc.wait(timeout=GRACEFUL + 30)
        except subprocess.TimeoutExpired:
            pass
        seconds = time.perf_counter() - t0
        assert proc.poll() is not None and seconds <= GRACEFUL + EXIT_SLACK, seconds
        for t in threads:                 # every client got an answer or a closed connection
            t.join(5)
        assert not any(t.is_alive() for t in threads) and len(answers) == len(requests), answers
    finally:
        if proc.poll() is None:
            proc.kill()
            proc.wait()
