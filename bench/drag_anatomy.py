"""Where a held drag's time goes, thread by thread: bench/slider.py's 3 s drag under a
Chromium trace.

For each round: the CPU time of each Chromium thread during the drag (its tasks' thread
time in the trace); the page's main thread's rendering (style, layout, pre-paint, paint,
layerisation, commit) and how many frames it rendered; the display compositor's frames
by the area they redrew (its damage: software compositing costs per damaged pixel); the
input events past 16.7 ms. Once: the nice value of each Chromium thread (Linux's /proc;
Chromium raises its display and IO threads) and whether the kernel shares the CPU
between sessions first (autogroups: then `nice` on the server does not weigh it against
Chromium). A diagnostic, not part of bench/run.py: the trace costs CPU itself.

    python bench/drag_anatomy.py [rounds] [--every] [--static DIR]
"""
from __future__ import annotations

import argparse
import collections
import glob
import json
import re
from pathlib import Path

import common  # first: puts the checkout on sys.path
import slider

#: trace categories: the timeline's task and rendering events, and the compositor's frames
CATEGORIES = ["devtools.timeline", "disabled-by-default-devtools.timeline", "toplevel", "cc", "viz"]
#: the main thread's rendering steps, as the trace names them
RENDERING = ("ProxyMain::BeginMainFrame", "UpdateLayoutTree", "Layout", "PrePaint", "Paint", "Layerize", "Commit")
#: damaged area of a compositor frame, Mpx: the bounds of the buckets reported
DAMAGE_BUCKETS = (0.02, 0.3, 0.8)
#: the threads whose nice is reported (as /proc names them: 15 characters): each process's
#: main thread, the compositors, IO, the held canvas's worker and the raster workers
NICE_OF = ("chromium", "VizCompositorTh", "Compositor", "Chrome_IOThread", "Chrome_ChildIOT",
           "DedicatedWorker", "CompositorTileW")


def thread_nices() -> dict:
    """{(process type, thread name): sorted nice values} of the Chromium threads now."""
    out = collections.defaultdict(set)
    for stat in glob.glob("/proc/[0-9]*/task/[0-9]*/stat"):
        pid = stat.split("/")[2]
        try:
            text = Path(stat).read_text()
            cmd = Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except OSError:
            continue                       # the thread ended meanwhile
        name = text[text.index("(") + 1:text.rindex(")")]
        if "chromium" not in cmd or name not in NICE_OF:
            continue
        kind = re.search(r"--type=(\S+)", cmd)
        nice = int(text[text.rindex(")") + 2:].split()[16])
        out[(kind[1] if kind else "browser", name)].add(nice)
    return {k: sorted(v) for k, v in sorted(out.items())}


def analyse(events: list) -> dict:
    """Per-thread CPU (ms), the main thread's rendering (ms) and frame count, and the
    compositor's frames bucketed by damaged area, from a trace's events."""
    names = {(e["pid"], e["tid"]): e["args"]["name"] for e in events
             if e.get("ph") == "M" and e.get("name") == "thread_name"}
    cpu, rendering, damage, frames = collections.Counter(), collections.Counter(), collections.Counter(), 0
    for e in events:
        if e.get("ph") != "X":
            continue
        thread = names.get((e["pid"], e["tid"]), str(e["tid"]))
        if e["name"] == "ThreadControllerImpl::RunTask":
            cpu[thread] += e.get("tdur", 0) / 1000
        elif thread == "CrRendererMain" and e["name"] in RENDERING:
            rendering[e["name"]] += e.get("tdur", 0) / 1000
            frames += e["name"] == "ProxyMain::BeginMainFrame"
        elif e["name"] == "DirectRenderer::DrawFrame ProcessForOverlays":
            w, h = (int(x) for x in re.search(r"(\d+)x(\d+)", e["args"]["root_damage_rect"]).groups())
            bucket = sum(w * h / 1e6 >= b for b in DAMAGE_BUCKETS)
            damage[bucket] += 1
    return {"thread_cpu_ms": dict(cpu.most_common(8)), "main_frames": frames,
            "main_rendering_ms": {k: round(v, 1) for k, v in rendering.items()},
            "compositor_frames_by_damage": [damage[b] for b in range(len(DAMAGE_BUCKETS) + 1)]}


def run(rounds: int, every: bool, static: str | None) -> tuple[dict, list[dict]]:
    from playwright.sync_api import sync_playwright
    env = {"BRDF_STATIC_DIR": static} if static else None
    results = []
    with common.server(env) as base, sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=slider.CHROMIUM, args=slider.CHROMIUM_ARGS, headless=True)
        try:
            page = browser.new_context(viewport=slider.VIEWPORT).new_page()
            url = base + "/"
            if every:
                slider.open_page(page, url)
                url += "?show=" + ",".join(page.evaluate("() => window.__brdf.panels().map((p) => p.name)"))
            for _ in range(rounds):
                ids = slider.open_page(page, url)
                positions = slider.drag_positions()
                page.evaluate(slider.MOVES_JS, [positions[:1], ids])      # the hand takes the thumb there
                browser.start_tracing(page=page, categories=CATEGORIES)
                drag = page.evaluate(slider.DRAG_JS, [positions, ids, slider.DRAG_HZ])
                raw = json.loads(browser.stop_tracing())
                found = analyse(raw["traceEvents"] if isinstance(raw, dict) else raw)
                found["late_ms"] = [round(h, 1) for h in drag["handled"] if h > slider.LATE_MS]
                results.append(found)
            nices = thread_nices()
        finally:
            browser.close()
    return nices, results


def report(nices: dict, results: list[dict]) -> list[str]:
    autogroup = Path("/proc/sys/kernel/sched_autogroup_enabled")
    lines = [f"autogroups (CPU shared between sessions first): "
             f"{autogroup.read_text().strip() == '1' if autogroup.exists() else 'unknown'}",
             "Chromium threads' nice (a renderer's main thread is 'renderer/chromium'): "
             + "; ".join(f"{kind}/{name} {v}" for (kind, name), v in nices.items())]
    edges = ", ".join(f"{b:g}" for b in DAMAGE_BUCKETS)
    for k, r in enumerate(results):
        lines.append(f"round {k + 1}: late events {r['late_ms'] or 'none'}")
        lines.append("  CPU ms by thread: " + ", ".join(f"{t} {v:.0f}" for t, v in r["thread_cpu_ms"].items()))
        lines.append(f"  main thread: {r['main_frames']} frames rendered; ms: "
                     + ", ".join(f"{n} {v}" for n, v in r["main_rendering_ms"].items()))
        lines.append(f"  compositor frames by damaged Mpx (edges {edges}): {r['compositor_frames_by_damage']}")
    return lines


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("rounds", nargs="?", type=int, default=2)
    ap.add_argument("--every", action="store_true", help="the page with every panel shown")
    ap.add_argument("--static", help="serve this static/ directory instead of the checkout's")
    args = ap.parse_args()
    print("\n".join(report(*run(args.rounds, args.every, args.static))))
