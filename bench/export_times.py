"""Export times: SVG and PNG through the API (first request starts Chromium; warm ones
reuse it), and a one-off CLI export (a fresh process: Python, imports, Chromium).

    python bench/export_times.py [--repeat 10]

Not a test: the numbers depend on the machine and on what else runs on it.
"""
from __future__ import annotations

import argparse
import statistics
import subprocess
import sys
import tempfile
import time
import warnings
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[1]))

with warnings.catch_warnings():
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient

from app.config import Settings  # noqa: E402
from app.main import create_app  # noqa: E402

URLS = {"svg": "/api/v1/figures/lobe.svg?alpha=0.2&theta_i_deg=60",
        "png": "/api/v1/figures/lobe.png?alpha=0.2&theta_i_deg=60&width=1200&height=800&scale=2"}


def timed(client, url) -> tuple[float, str]:
    t0 = time.perf_counter()
    r = client.get(url)
    dt = time.perf_counter() - t0
    assert r.status_code == 200, r.text
    return dt, r.headers.get("server-timing", "")


def main() -> None:
    ap = argparse.ArgumentParser()
    ap.add_argument("--repeat", type=int, default=10)
    args = ap.parse_args()
    client = TestClient(create_app(Settings()))
    client.get("/api/v1/figures/lobe?alpha=0.2&theta_i_deg=60")        # warm the numerics
    for fmt, url in URLS.items():
        first, timing = timed(client, url)
        warm = [timed(client, url)[0] for _ in range(args.repeat)]
        print(f"{fmt.upper()} first {first * 1000:7.0f} ms ({timing})   warm median "
              f"{statistics.median(warm) * 1000:5.0f} ms  min {min(warm) * 1000:4.0f}  "
              f"max {max(warm) * 1000:4.0f}  (n={args.repeat})")
    with tempfile.TemporaryDirectory() as tmp:
        for ext in ("svg", "png", "csv"):
            t0 = time.perf_counter()
            subprocess.run([sys.executable, "-m", "app.cli", "export", "lobe", "--alpha", "0.2",
                            "--theta-i-deg", "60", "-o", f"{tmp}/lobe.{ext}"], check=True,
                           capture_output=True, cwd=Path(__file__).resolve().parents[1])
            print(f"CLI one-off export to .{ext} (new process): {(time.perf_counter() - t0) * 1000:6.0f} ms")


if __name__ == "__main__":
    main()
