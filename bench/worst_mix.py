"""The worst-case mix of issue 36: c = 8 slider-like cheap GETs against a real server,
first quiet, then beside each heavy request, on 1 and 2 uvicorn workers: cheap p50/p99
against the quiet baseline (measured while the heavy request runs), the heavy request's
status and seconds (0: no answer within HEAVY_TIMEOUT), peak RSS of the
server's processes, errors. Loopback only; bounded in count and time.

    python bench/worst_case.py --mix                  # 1 and 2 workers (~3 min)
    python bench/worst_mix.py --workers 1 --seconds 4
"""
from __future__ import annotations

import argparse
import json
import os
import random
import struct
import subprocess
import sys
import threading
import time
import urllib.error
import urllib.request
import zlib
from pathlib import Path

import common  # first: puts the checkout on sys.path

CHEAP = ["/api/v1/figures/lobe?alpha={a}&theta_i_deg=40", "/api/v1/figures/ndf?alpha={a}",
         "/api/v1/figures/g1?alpha={a}", "/api/v1/ndf?alpha={a}&n=181"]
#: concurrent cheap clients (a page's sliders: the issue's c = 8)
CONCURRENCY = 8
#: seconds a heavy request is waited for (the issue saw 10 minutes for one upload)
HEAVY_TIMEOUT = 120.0


def _samples_csv(rows: int) -> bytes:
    rng = random.Random(1)
    lines = ["theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f"]
    lines += [f"{rng.uniform(0, 89):.4f},0,{rng.uniform(0, 89):.4f},{rng.uniform(0, 359):.4f},"
              f"{rng.uniform(0.01, 3):.5f}" for _ in range(rows)]
    return ("\n".join(lines) + "\n").encode()


def _png_bomb(side: int, raw_bytes: int) -> bytes:
    """A valid PNG header declaring side×side 16-bit RGB, and a zlib stream of zeros that
    inflates to ``raw_bytes``: what POST /lut/check must refuse before inflating."""
    def chunk(kind, data):
        return struct.pack(">I", len(data)) + kind + data + struct.pack(">I", zlib.crc32(kind + data))
    ihdr = struct.pack(">IIBBBBB", side, side, 16, 2, 0, 0, 0)
    return (b"\x89PNG\r\n\x1a\n" + chunk(b"IHDR", ihdr)
            + chunk(b"IDAT", zlib.compress(b"\0" * raw_bytes, 9)) + chunk(b"IEND", b""))


def heavy_requests() -> dict:
    """name → (method, path, body, content type): one of each heavy request of issue 36
    at the default limits (bench/worst_heavy.py times each alone)."""
    import worst_heavy
    everything = worst_heavy.cases()
    upload = next(k for k in everything if k.startswith("upload") and "warm" in k)
    export = "/api/v1/export/model.csv?n_theta=91&n_phi=360"
    return {
        upload.replace(", warm", ""): everything[upload],
        "samples CSV 200k rows (8 MB)": ("POST", "/api/v1/datasets", _samples_csv(200_000), "text/csv"),
        # a batch answers figures only: 16 of the costliest the page can ask
        "batch of 16 sphere_env figures": ("POST", "/api/v1/batch", json.dumps({"requests": [
            f"/api/v1/figures/sphere_env?n=256&samples=32&environment=studio&seed={k}"
            for k in range(16)]}).encode(), "application/json"),
        "batch of 16 samples.csv 200 000": everything["batch 16 x samples.csv 200 000"],
        "sphere_env 512 px x 61 samples, principled": (
            "GET", "/api/v1/figures/sphere_env?model=principled&n=512&samples=61&environment="
                   "studio&clearcoat=1&sheen=1", None, None),
        "sphere_env 512 px x 8 samples, principled, PNG": (
            "GET", "/api/v1/figures/sphere_env.png?model=principled&n=512&samples=8&environment="
                   "studio&clearcoat=1&sheen=1", None, None),
        "model.csv 91x360": ("GET", export, None, None),
        "lut/check 256^2 JSON": everything["lut/check 256^2 JSON"],
        "PNG bomb 62 KB -> 8000x8000": ("POST", "/api/v1/lut/check?kind=split_sum",
                                        _png_bomb(8000, 64_000_000), "image/png"),
    }


def _request(base, method, path, body=None, ctype=None, timeout=60.0):
    req = urllib.request.Request(base + path, data=body, method=method,
                                 headers={"content-type": ctype} if ctype else {})
    t0 = time.perf_counter()
    try:
        with urllib.request.urlopen(req, timeout=timeout) as res:
            res.read()
            status = res.status
    except urllib.error.HTTPError as e:
        e.read()
        status = e.code
    except OSError:
        status = 0
    return status, time.perf_counter() - t0


def _tree_rss(pid: int) -> int:
    """Resident bytes of ``pid`` and its children (the uvicorn workers)."""
    total = 0
    pids = [pid]
    try:
        pids += [int(p) for p in Path(f"/proc/{pid}/task/{pid}/children").read_text().split()]
    except OSError:
        pass
    for p in pids:
        try:
            for line in Path(f"/proc/{p}/status").read_text().splitlines():
                if line.startswith("VmRSS:"):
                    total += int(line.split()[1]) * 1024
        except OSError:
            pass
    return total


def _cheap_load(base, seconds, until: threading.Event | None = None):
    """c = CONCURRENCY clients for ``seconds``, and on until ``until`` is set (the heavy
    request answered; HEAVY_TIMEOUT at most): (latencies, errors)."""
    lat, errors, lock = [], [0], threading.Lock()
    start = time.monotonic()

    def going():
        elapsed = time.monotonic() - start
        return elapsed < seconds or (until is not None and not until.is_set()
                                     and elapsed < HEAVY_TIMEOUT)

    def client(k):
        rng = random.Random(k)
        while going():
            path = rng.choice(CHEAP).format(a=round(rng.uniform(0.05, 0.9), 3))
            status, s = _request(base, "GET", path, timeout=30)
            with lock:
                lat.append(s)
                errors[0] += status != 200
    threads = [threading.Thread(target=client, args=(k,)) for k in range(CONCURRENCY)]
    for t in threads:
        t.start()
    for t in threads:
        t.join()
    return lat, errors[0]


def run(workers: int, seconds: float) -> list[dict]:
    port = common.free_port()
    base = f"http://127.0.0.1:{port}"
    proc = subprocess.Popen([sys.executable, "-m", "app.cli", "serve", "--host", "127.0.0.1",
                             "--port", str(port), "--workers", str(workers)],
                            cwd=common.ROOT, stdout=subprocess.DEVNULL, stderr=subprocess.DEVNULL,
                            env={**os.environ, "PYTHONPATH": str(common.ROOT)})
    try:
        deadline = time.monotonic() + 120
        while time.monotonic() < deadline and _request(base, "GET", "/api/v1/health", timeout=2)[0] != 200:
            time.sleep(0.3)
        _cheap_load(base, 2)                       # warm every worker
        # and the heavy pool's: a worker starts ~1 s after the server, in 2-10 s
        while time.monotonic() < deadline and _request(
                base, "GET", "/api/v1/export/model.csv?n_theta=2&n_phi=1", timeout=20)[0] != 200:
            time.sleep(0.5)
        rows = []
        quiet, quiet_err = _cheap_load(base, seconds)
        rows.append({"case": "quiet", "p50_ms": common.percentile(quiet, 50) * 1e3,
                     "p99_ms": common.percentile(quiet, 99) * 1e3, "errors": quiet_err,
                     "rss_mb": _tree_rss(proc.pid) / 2**20})
        for name, (method, path, body, ctype) in heavy_requests().items():
            peak, done, heavy = [0], threading.Event(), {}

            def watch():
                while not done.is_set():
                    peak[0] = max(peak[0], _tree_rss(proc.pid))
                    time.sleep(0.1)

            answered = threading.Event()

            def fire():
                heavy["status"], heavy["s"] = _request(base, method, path, body, ctype,
                                                       timeout=HEAVY_TIMEOUT)
                answered.set()
            watcher, firer = threading.Thread(target=watch), threading.Thread(target=fire)
            watcher.start()
            firer.start()
            lat, err = _cheap_load(base, seconds, until=answered)
            firer.join(HEAVY_TIMEOUT)
            done.set()
            watcher.join()
            rows.append({"case": name, "p50_ms": common.percentile(lat, 50) * 1e3,
                         "p99_ms": common.percentile(lat, 99) * 1e3, "errors": err,
                         "heavy": f"{heavy.get('status')} in {heavy.get('s', float('nan')):.1f} s",
                         "rss_mb": peak[0] / 2**20})
        return rows
    finally:
        proc.terminate()
        try:
            proc.wait(timeout=30)
        except subprocess.TimeoutExpired:
            proc.kill()
            proc.wait()


def main(argv=None) -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--workers", type=int, nargs="+", default=[1, 2])
    parser.add_argument("--seconds", type=float, default=6.0, help="of cheap load per case")
    args = parser.parse_args(argv)
    print(f"load average at start: {common.loadavg()}")
    print("| workers | case | cheap p50 ms | cheap p99 ms | p99 / quiet | errors | heavy | peak RSS MB |")
    print("|---|---|---|---|---|---|---|---|")
    for w in args.workers:
        rows = run(w, args.seconds)
        q = rows[0]["p99_ms"]
        for r in rows:
            print(f"| {w} | {r['case']} | {r['p50_ms']:.1f} | {r['p99_ms']:.1f} | "
                  f"{r['p99_ms'] / q:.1f}× | {r['errors']} | {r.get('heavy', '—')} | {r['rss_mb']:.0f} |",
                  flush=True)
    print(f"load average at end: {common.loadavg()}")


if __name__ == "__main__":
    main()
