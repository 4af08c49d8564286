"""The export browser's memory, apart from the soak: does kaleido's Chromium keep growing
when it only draws, and what does replacing it cost (app/export/renderer_memory.py).

    python bench/renderer_growth.py --images 1500     # its tree after each collection
    python bench/renderer_growth.py --restarts 4      # what a replacement costs

--images: one process draws the soak's lobe PNGs (800×500, α 0.05-0.94) back to back;
after each collection (every COLLECT_EVERY images, the browser at rest) its tree is read
by process type (browser, renderer, gpu-process, zygote, utilities), PSS and anonymous
PSS (Pss_Anon + Pss_Shmem): one JSON line a reading. The replacement's bound is off, so
the browser is the one browser throughout.

--restarts: a new browser opened beside the running one (as image.py's replacement does)
N times: its start's wall seconds, its tree's CPU seconds and anonymous MB once open, and
the time of exports drawn by the old browser meanwhile against exports drawn without.
"""
from __future__ import annotations

import argparse
import json
import os
import statistics
import threading
import time
import warnings

import common  # first: puts the checkout on sys.path

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient

from app.export import renderer_memory
from app.export.image import ImageRenderer, _close_browser
from app.main import create_app
from tests.budget import settings_for_tests


def _tree(pid: int) -> set[int]:
    """``pid`` and its descendants now (none left: the empty set)."""
    return renderer_memory.descendants(pid) or set()


def _by_type(pid: int) -> dict[str, float]:
    """MB of ``pid``'s tree by Chromium process type: PSS as "<type>", anonymous PSS as
    "anon:<type>", and the totals "pss" and "anon"."""
    out: dict[str, float] = {}
    for p in _tree(pid):
        try:
            cmd = open(f"/proc/{p}/cmdline", "rb").read().replace(b"\0", b" ").decode(errors="replace")
            f = {line.split(":")[0]: int(line.split()[1])
                 for line in open(f"/proc/{p}/smaps_rollup") if line.startswith("Pss")}
        except (OSError, ValueError, IndexError):
            continue
        kind = cmd.split("--type=")[1].split()[0] if "--type=" in cmd else (
            "browser" if "chrom" in cmd and "wrapper" not in cmd else "launcher")
        if "--utility-sub-type=" in cmd:
            kind += ":" + cmd.split("--utility-sub-type=")[1].split()[0].split(".")[-1]
        anon = (f.get("Pss_Anon", 0) + f.get("Pss_Shmem", 0)) / 1024
        out[kind] = out.get(kind, 0.0) + f["Pss"] / 1024
        out["anon:" + kind] = out.get("anon:" + kind, 0.0) + anon
        out["pss"] = out.get("pss", 0.0) + f["Pss"] / 1024
        out["anon"] = out.get("anon", 0.0) + anon
    return {k: round(v, 1) for k, v in sorted(out.items())}


def _cpu_seconds(pids: set[int]) -> float:
    tick, total = os.sysconf("SC_CLK_TCK"), 0
    for p in pids:
        try:
            f = open(f"/proc/{p}/stat").read().rsplit(")", 1)[1].split()
            total += int(f[11]) + int(f[12])
        except (OSError, IndexError, ValueError):
            continue
    return total / tick


def growth(r: ImageRenderer, figures: list, images: int) -> None:
    r.memory.bound_mb = float("inf")          # the one browser throughout
    t0 = time.monotonic()
    for k in range(images):
        r.render(figures[k % len(figures)], "png", 800, 500, 1)
        if (k + 1) % r.memory.every == 0:
            r.memory.last.result(30)
            time.sleep(0.5)
            row = {"t": round(time.monotonic() - t0, 1), "images": k + 1,
                   **_by_type(renderer_memory.browser_pid(r._kaleido))}
            print(json.dumps(row), flush=True)


def restarts(r: ImageRenderer, figures: list, n: int) -> None:
    for k in range(10):                        # warm
        r.render(figures[k], "png", 800, 500, 1)
    quiet = []
    for k in range(10):
        t0 = time.perf_counter()
        r.render(figures[k], "png", 800, 500, 1)
        quiet.append(time.perf_counter() - t0)
    walls, cpus, mbs, during = [], [], [], []
    for i in range(n):
        box = {}

        def opener():
            t0 = time.perf_counter()
            loop, k = r._open()
            box["wall"] = time.perf_counter() - t0
            pid = renderer_memory.browser_pid(k)
            box["cpu"], box["mb"], box["browser"] = (_cpu_seconds(_tree(pid)),
                                                     renderer_memory.tree_anon_mb(pid), (loop, k))
        th = threading.Thread(target=opener)
        th.start()
        while th.is_alive():
            t0 = time.perf_counter()
            r.render(figures[i], "png", 800, 500, 1)
            during.append(time.perf_counter() - t0)
        th.join()
        walls.append(box["wall"])
        cpus.append(box["cpu"])
        mbs.append(box["mb"])
        _close_browser(*box["browser"])
        time.sleep(1)
    print(json.dumps({"start_wall_s": [round(w, 2) for w in walls], "start_cpu_s": cpus,
                      "new_tree_anon_mb": [round(m) for m in mbs],
                      "export_s_quiet": {"median": round(statistics.median(quiet), 2), "max": round(max(quiet), 2)},
                      "export_s_during_start": {"n": len(during), "median": round(statistics.median(during), 2),
                                                "max": round(max(during), 2)}}))


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--images", type=int, default=0)
    parser.add_argument("--restarts", type=int, default=0)
    args = parser.parse_args()
    client = TestClient(create_app(settings_for_tests()))
    figures = [client.get(f"/api/v1/figures/lobe?alpha={0.05 + 0.01 * k:.2f}").json() for k in range(90)]
    r = ImageRenderer(os.environ.get("BRDF_CHROMIUM") or None)
    try:
        if args.images:
            growth(r, figures, args.images)
        if args.restarts:
            restarts(r, figures, args.restarts)
    finally:
        r.close()


if __name__ == "__main__":
    main()
