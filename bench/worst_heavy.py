"""Issue 36's heavy requests at the default limits against a real `brdf-explorer serve`
(one worker, one heavy-pool process): each must answer within BRDF_MAX_SECONDS + 1 s
(a 2xx, or its 413/503 with the reason), and SIGTERM while one runs must end the server
within its graceful timeout (serve's default: BRDF_MAX_SECONDS + 1 s).

    python bench/worst_heavy.py                 # every request, then SIGTERM during five
    python bench/worst_heavy.py --no-sigterm    # the requests only
    python bench/worst_heavy.py --only upload   # the cases whose name holds a word
    python bench/worst_heavy.py --workers2      # an upload's id on 2 workers and a restart

"cold" is the first request after /api/v1/health answers (the pool's worker may still be
starting); the rest run one after another on the same server, each timed from its first
byte sent to its last byte read. Loopback only; bounded: every request times out at
60 s, every server is stopped by its pid. Not a test: it measures and prints a table.
"""
from __future__ import annotations

import argparse
import json
import os
import random
import signal
import struct
import subprocess
import sys
import time
import urllib.error
import urllib.request
import zlib

import common  # first: puts the checkout on sys.path
from tests.live import free_port, healthy

from app.config import Settings

#: the default budget (BRDF_MAX_SECONDS) every answer must fit in, plus this
GRACE = 1.0
#: seconds a request is waited for at most (a hang shows as 0 in 60 s)
TIMEOUT = 60.0
#: seconds a case is retried while the pool's worker starts (it took 16 s at load 17)
START_WAIT = 40.0
PRINCIPLED = "model=principled&clearcoat=1&sheen=1&specular_tint=0.5&anisotropic=0.5"


def samples_csv(rows: int, seed: int) -> bytes:
    """A samples CSV of ``rows`` rows, nearly every one its own direction pair (the
    summary's worst case: as many groups as rows allow); ~40 bytes a row."""
    rng = random.Random(seed)
    out = ["theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f"]
    out += [f"{rng.uniform(0, 89):.4f},0,{rng.uniform(0, 89):.4f},{rng.uniform(0, 359):.4f},"
            f"{rng.uniform(0.01, 3):.5f}" for _ in range(rows)]
    return ("\n".join(out) + "\n").encode()


def png_bomb(side: int, raw_bytes: int, bits: int = 16) -> bytes:
    """A PNG header declaring side × side RGB over a zlib stream of zeros inflating to
    ``raw_bytes`` (ISO/IEC 15948 chunks: length, type, data, CRC-32)."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    stream = zlib.compressobj(9)
    piece = b"\0" * (1 << 20)
    body = b"".join(stream.compress(piece) for _ in range(raw_bytes >> 20)) + stream.flush()
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", struct.pack(">IIBBBBB", side, side, bits, 2, 0, 0, 0))
            + chunk(b"IDAT", body) + chunk(b"IEND", b""))


def lut_json(n: int) -> bytes:
    """A full-size (n × n × 2) split-sum table as JSON: the most /lut/check infers."""
    rng = random.Random(3)
    return json.dumps({"values": [[[rng.random(), rng.random()] for _ in range(n)]
                                  for _ in range(n)]}).encode()


def cases() -> dict:
    """name → (method, path, body, content type): the costliest request of each heavy
    route the default limits allow (uploads at BRDF_MAX_UPLOAD_BYTES)."""
    s = Settings()
    rows = s.max_upload_bytes // 41          # ~870 000 rows fit the upload limit
    upload = samples_csv(rows, 1)
    while len(upload) > s.max_upload_bytes:
        rows -= 20_000
        upload = samples_csv(rows, 1)
    sphere = f"/api/v1/figures/sphere_env?{PRINCIPLED}&n=512&samples=61&environment=studio"
    deep = b'{"values":' + b"[" * 1000 + b"]" * 1000 + b"}"
    return {
        f"upload {rows} rows ({len(upload) / 1e6:.0f} MB), cold": ("POST", "/api/v1/datasets", upload, "text/csv"),
        f"upload {rows} rows, warm": ("POST", "/api/v1/datasets", samples_csv(rows, 2), "text/csv"),
        "batch 16 x sphere_env 256 px x 32": ("POST", "/api/v1/batch", json.dumps({"requests": [
            f"/api/v1/figures/sphere_env?n=256&samples=32&environment=studio&seed={k}"
            for k in range(16)]}).encode(), "application/json"),
        "batch 16 x samples.csv 200 000": ("POST", "/api/v1/batch", json.dumps({"requests": [
            f"/api/v1/figures/samples.csv?n=200000&alpha={0.1 + k / 100}" for k in range(16)]}).encode(),
            "application/json"),
        "sphere_env 512 x 61 principled (json)": ("GET", sphere, None, None),
        "sphere_env 512 x 61 principled (svg)": ("GET", sphere.replace("sphere_env?", "sphere_env.svg?"), None, None),
        "sphere_env 512 x 61 principled (png)": ("GET", sphere.replace("sphere_env?", "sphere_env.png?"), None, None),
        "sphere_env 512 x 8 principled (json)": ("GET", sphere.replace("samples=61", "samples=8"), None, None),
        "model.csv 91 x 360 principled": ("GET", f"/api/v1/export/model.csv?{PRINCIPLED}&n_theta=91&n_phi=360", None, None),
        "model.csv 91 x 360 smith_numeric": ("GET", "/api/v1/export/model.csv?masking=smith_numeric&n_theta=91&n_phi=360", None, None),
        "model.binary principled": ("GET", f"/api/v1/export/model.binary?{PRINCIPLED}", None, None),
        "samples.csv 200 000": ("GET", "/api/v1/figures/samples.csv?n=200000&alpha=1e-4&alpha_y=1", None, None),
        "lut/check 256^2 JSON": ("POST", "/api/v1/lut/check?kind=split_sum", lut_json(256), "application/json"),
        "lut/check PNG bomb 8000^2 (62 KB)": ("POST", "/api/v1/lut/check?kind=split_sum",
                                              png_bomb(8000, 64 << 20), "image/png"),
        "lut/check PNG bomb 256^2 -> 1 GB (1 MB)": ("POST", "/api/v1/lut/check?kind=split_sum",
                                                    png_bomb(256, 1 << 30), "image/png"),
        "lut/check JSON 1000 deep": ("POST", "/api/v1/lut/check?kind=split_sum", deep, "application/json"),
    }


def request(base: str, method: str, path: str, body=None, ctype=None) -> tuple[int, float, str]:
    """(status, seconds, the first words of an error's message)."""
    req = urllib.request.Request(base + path, data=body, method=method,
                                 headers={"content-type": ctype} if ctype else {})
    t0 = time.perf_counter()
    try:
        with urllib.request.urlopen(req, timeout=TIMEOUT) as res:
            res.read()
            return res.status, time.perf_counter() - t0, ""
    except urllib.error.HTTPError as e:
        text = e.read().decode(errors="replace")
        seconds = time.perf_counter() - t0
        try:
            text = json.loads(text)["detail"][0]["msg"]
        except (ValueError, KeyError, IndexError, TypeError):
            pass
        return e.code, seconds, text[:90]
    except OSError as e:
        return 0, time.perf_counter() - t0, type(e).__name__


def start(env: dict | None = None) -> tuple[str, subprocess.Popen]:
    """`python -m app.cli serve` on a free port (its own graceful-timeout default)."""
    port = free_port()
    base = f"http://127.0.0.1:{port}"
    proc = subprocess.Popen([sys.executable, "-m", "app.cli", "serve", "--host", "127.0.0.1",
                             "--port", str(port)], cwd=common.ROOT, stdout=subprocess.DEVNULL,
                            stderr=subprocess.DEVNULL,
                            env={**os.environ, "PYTHONPATH": str(common.ROOT), **(env or {})})
    deadline = time.monotonic() + 120
    while not healthy(base):
        if proc.poll() is not None or time.monotonic() > deadline:
            raise RuntimeError("the server did not start")
        time.sleep(0.1)
    return base, proc


def stop(proc: subprocess.Popen) -> float:
    """SIGTERM, and the seconds until the process (and so its pool) ended; SIGKILL at 60 s."""
    t0 = time.perf_counter()
    proc.send_signal(signal.SIGTERM)
    try:
        proc.wait(timeout=60)
    except subprocess.TimeoutExpired:
        proc.kill()
        proc.wait()
        return float("inf")
    return time.perf_counter() - t0


def two_workers(env: dict) -> None:
    """`serve --workers 2`: an upload, then 100 GETs of its id (the kernel spreads the
    connections over both workers), then a restart on the same cache directory and one
    GET more (200, or 410 with the reason if it was evicted)."""
    def serve():
        port = free_port()
        base = f"http://127.0.0.1:{port}"
        proc = subprocess.Popen([sys.executable, "-m", "app.cli", "serve", "--host", "127.0.0.1",
                                 "--port", str(port), "--workers", "2"], cwd=common.ROOT,
                                stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                                env={**os.environ, "PYTHONPATH": str(common.ROOT), **env})
        deadline = time.monotonic() + 120
        while not healthy(base):
            if proc.poll() is not None or time.monotonic() > deadline:
                raise RuntimeError("the server did not start")
            time.sleep(0.2)
        return base, proc
    base, proc = serve()
    try:
        body = samples_csv(2000, 5)
        for _ in range(30):                   # the pools' workers may still be starting
            req = urllib.request.Request(base + "/api/v1/datasets", data=body, method="POST",
                                         headers={"content-type": "text/csv"})
            try:
                with urllib.request.urlopen(req, timeout=TIMEOUT) as res:
                    data_id = json.loads(res.read())["id"]
                    break
            except urllib.error.HTTPError as e:
                e.read()
                time.sleep(1)
        statuses = [request(base, "GET", f"/api/v1/datasets/{data_id}")[0] for _ in range(100)]
    finally:
        stop(proc)
    base, proc = serve()
    try:
        after = request(base, "GET", f"/api/v1/datasets/{data_id}")
    finally:
        stop(proc)
    print(f"\n--workers 2: {statuses.count(200)} of {len(statuses)} GETs of a just-uploaded id "
          f"answered 200 (others: {sorted(set(statuses) - {200})}); after a restart: {after[0]} {after[2]}")


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--no-sigterm", action="store_true")
    parser.add_argument("--only", default="")
    parser.add_argument("--workers2", action="store_true",
                        help="only the --workers 2 check of an upload's id")
    args = parser.parse_args(argv)
    if args.workers2:
        import tempfile
        with tempfile.TemporaryDirectory() as cache:
            two_workers({"BRDF_CACHE_DIR": cache})
        return
    limit = Settings().max_seconds + GRACE
    todo = {k: v for k, v in cases().items() if args.only in k}
    print(f"load average at start: {common.loadavg()}; limit {limit:g} s")
    print("| request | status | seconds | within | message |")
    print("|---|---|---|---|---|")
    base, proc = start()
    try:
        for name, (method, path, body, ctype) in todo.items():
            # a 503 "still starting" (the pool's worker replacing one cut by the case
            # before) is waited out, up to START_WAIT s, so that each case meets a started
            # worker; every attempt counts against the limit, the slowest is printed
            give_up, attempts, slowest = time.monotonic() + START_WAIT, 0, 0.0
            while True:
                status, seconds, msg = request(base, method, path, body, ctype)
                attempts, slowest = attempts + 1, max(slowest, seconds)
                if status != 503 or "starting" not in msg or time.monotonic() > give_up:
                    break
                time.sleep(1.0)
            ok = status != 0 and status < 500 or status == 503
            print(f"| {name} | {status} | {seconds:.2f} | {'yes' if ok and slowest <= limit else 'NO'} | "
                  f"{msg} |" + (f" ({attempts - 1} × 503 starting first, the slowest {slowest:.2f} s)"
                                if attempts > 1 else ""), flush=True)
    finally:
        stop(proc)
    if args.no_sigterm:
        return
    print("\nSIGTERM 1 s into each (graceful timeout: serve's default, BRDF_MAX_SECONDS + 1 s)")
    print("| request running | exit seconds | within |")
    print("|---|---|---|")
    picks = [k for k in todo if "warm" in k or "16 x samples" in k or "(png)" in k
             or "smith_numeric" in k or "256^2 JSON" in k]
    for name in picks:
        method, path, body, ctype = todo[name]
        base, proc = start()
        time.sleep(3)                          # the pool's worker started
        import threading
        t = threading.Thread(target=request, args=(base, method, path, body, ctype), daemon=True)
        t.start()
        time.sleep(1.0)
        seconds = stop(proc)
        print(f"| {name} | {seconds:.2f} | {'yes' if seconds <= limit else 'NO'} |", flush=True)
    print(f"load average at end: {common.loadavg()}")


if __name__ == "__main__":
    main()
