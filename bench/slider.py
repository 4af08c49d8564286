"""Slider to pixels: headless Chromium (Debian's, driven by Playwright) on the real app,
1400 × 900, the default page and the page with every panel shown.

Single moves: for each of N moves of the α slider, the time from the slider's `input`
event to the last finished draw (the page's own draw event, `brdf-drawn`, at the time it
states: when the chart's worker finished painting the canvas) among the panels in the viewport (every shown panel depends on α), the page let go quiet between moves. Median and p95.

Sustained drag: the slider pressed (pointerdown) where its thumb is, 60 `input` events
a second for 3 s, then released (change, pointerup), as a hand drags it. The thumb is
first moved to where the drag starts (a single move, not timed): a drag's events are
consecutive positions, and a jump of the thumb is what the single moves measure. Reported: redraws per second of
each panel in view during the drag; the settle time (last event → the page quiet, the
full-resolution redraw after the release included); and how promptly each input event
was handled: the lateness of its timer (the main thread busy drawing delays it) plus the
time its handler ran, p95 and max, against one 60 Hz frame (16.7 ms), and for each event
past it the two parts apart. On Linux also the
CPU time of Chromium and the server during the drag, and how long the page's main thread
was runnable but waiting for a CPU (/proc's schedstat): the part of a late event that is
the machine's, not the page's.

``python bench/slider.py [--static DIR]``: DIR serves another page (e.g. an older
checkout's: ``git archive <commit> static | tar -x -C /tmp/before``, then
``--static /tmp/before/static``) against the same server, for a before/after table.
"""
from __future__ import annotations

import argparse
import glob
import os
from pathlib import Path

import common  # first: puts the checkout on sys.path

CHROMIUM = os.environ.get("BRDF_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
VIEWPORT = {"width": 1400, "height": 900}
DRAG_HZ, DRAG_SECONDS = 60, 3.0
#: an input event is late past one frame at 60 Hz (issue 12: "handled within 16 ms")
LATE_MS = 1000 / 60

# The plot divs in the viewport (a shown panel's plot whose box meets the window).
IN_VIEW_JS = """() => [...document.querySelectorAll('.plot')].filter((d) => {
  const r = d.getBoundingClientRect();
  return d.offsetParent !== null && r.width > 0 && r.bottom > 0 && r.top < innerHeight
    && r.right > 0 && r.left < innerWidth; }).map((d) => d.id)"""

QUIET_JS = """(ids) => window.__brdf && window.__brdf.pending() === 0
    && ids.every((id) => { const d = document.getElementById(id); return d && d.layout; })"""

# In the page: hooks the end of each draw on every plot div (the page's own event), and a
# quiet-wait helper.
HOOK_JS = """() => {
  window.__bench = { events: [] };
  const name = window.__brdf.drawEvent;
  for (const d of document.querySelectorAll('.plot')) {
    if (d.__benchHooked) continue;
    d.__benchHooked = true;
    // the draw's own time where the page gives it (a chart painted in its worker tells
    // when; the event comes a task later), else the event's
    d.addEventListener(name, (e) => window.__bench.events.push([d.id,
      e.detail?.paintedAt ? e.detail.paintedAt - performance.timeOrigin : performance.now()]));
  }
  window.__bench.quiet = async (since, deadline) => {
    const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
    for (;;) {
      await sleep(5);
      const ev = window.__bench.events, now = performance.now();
      const last = ev.length ? Math.max(since, ev[ev.length - 1][1]) : since;
      if (window.__brdf.pending() === 0 && now - last > 60) return last;
      if (now > deadline) return NaN;
    }
  };
}"""

MOVES_JS = """async ([positions, ids]) => {
  const slider = document.getElementById('alpha-slider');
  const out = [];
  for (const pos of positions) {
    window.__bench.events.length = 0;
    const t0 = performance.now();
    slider.value = String(pos);
    slider.dispatchEvent(new Event('input', { bubbles: true }));
    await window.__bench.quiet(t0, t0 + 20000);
    const drawn = {};
    for (const [id, t] of window.__bench.events) if (ids.includes(id) && t >= t0) drawn[id] = t - t0;
    const missing = ids.filter((id) => !(id in drawn));
    out.push({ ms: missing.length ? NaN : Math.max(...Object.values(drawn)), drawn });
  }
  return out;
}"""

DRAG_JS = """async ([positions, ids, hz]) => {
  const slider = document.getElementById('alpha-slider');
  const period = 1000 / hz;
  const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
  window.__bench.events.length = 0;
  // the first move is due one period after the grab: what the grab costs counts
  const start = performance.now() + period;
  slider.dispatchEvent(new PointerEvent('pointerdown', { bubbles: true }));
  const handled = [], split = [];      // split: [waited for its turn, its handler ran]
  let prevEnd = start;
  for (let k = 0; k < positions.length; k++) {
    const due = start + k * period;
    await sleep(Math.max(0, due - performance.now()));
    // from when this event could run (its time, or the previous one's end if that was
    // later) to the end of its handler: the main thread's other work plus its own
    const ready = Math.max(due, prevEnd), began = performance.now();
    slider.value = String(positions[k]);
    slider.dispatchEvent(new Event('input', { bubbles: true }));
    prevEnd = performance.now();
    handled.push(prevEnd - ready);
    split.push([began - ready, prevEnd - began]);
  }
  const last = performance.now();
  slider.dispatchEvent(new Event('change', { bubbles: true }));
  slider.dispatchEvent(new PointerEvent('pointerup', { bubbles: true }));
  const settled = await window.__bench.quiet(last, last + 30000);
  const during = (id) => window.__bench.events.filter((e) => e[0] === id && e[1] >= start && e[1] <= last).length;
  const rates = {};
  for (const id of ids) rates[id] = during(id) / ((last - start) / 1000);
  return { rates, settle_ms: settled - last, handled, split, seconds: (last - start) / 1000 };
}"""


def _threads() -> dict:
    """{(pid, tid): (cmdline, ns on a CPU, ns runnable but waiting for one)} of every
    Chromium and uvicorn thread (Linux's /proc/*/task/*/schedstat), {} elsewhere."""
    out = {}
    for stat in glob.glob("/proc/[0-9]*/task/[0-9]*/schedstat"):
        pid, tid = stat.split("/")[2], stat.split("/")[4]
        try:
            run, wait, _ = (int(x) for x in Path(stat).read_text().split())
            cmd = Path(f"/proc/{pid}/cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except (OSError, ValueError):
            continue                  # the thread ended meanwhile
        if "chromium" in cmd or "uvicorn" in cmd:
            out[(pid, tid)] = (cmd, run, wait)
    return out


def contention(before: dict, after: dict) -> dict:
    """What the CPUs did between two _threads() snapshots, ms: all Chromium and server
    threads' CPU time, and the page's main thread (the busiest renderer's first thread)
    on a CPU and runnable but waiting for one: a late input event is either the page's
    own work or this wait, when the machine's 2 cores have more to run than 2 threads."""
    new = (None, 0, 0)                # a thread started during the drag: all of its time
    delta = {k: (cmd, (run - before.get(k, new)[1]) / 1e6, (wait - before.get(k, new)[2]) / 1e6)
             for k, (cmd, run, wait) in after.items()}
    mains = [(run, wait) for (pid, tid), (cmd, run, wait) in delta.items() if pid == tid and "--type=renderer" in cmd]
    if not mains:
        return {}
    run, wait = max(mains)
    return {"cpu_ms": round(sum(cpu for _, cpu, _ in delta.values())), "main_run_ms": round(run),
            "main_wait_ms": round(wait)}


def _pct(xs, q):
    return round(common.percentile(xs, q), 1) if xs else float("nan")


def thread_ms(cdp) -> float:
    """CPU time of the page's main thread so far (Chromium's ThreadTime metric), ms: the
    page's own work, which a loaded machine stretches in wall time but does not inflate."""
    return 1000 * {m["name"]: m["value"] for m in cdp.send("Performance.getMetrics")["metrics"]}["ThreadTime"]


def open_page(page, url: str) -> list[str]:
    """Loads `url`, waits until every panel in view has drawn and nothing is pending,
    hooks the draws (HOOK_JS); returns the ids of the plots in view."""
    page.goto(url)
    page.wait_for_function("() => window.__brdf && window.__brdf.pending() === 0", timeout=60_000)
    ids = [i for i in page.evaluate(IN_VIEW_JS) if i.startswith("plot-")]
    page.wait_for_function(QUIET_JS, arg=ids, timeout=60_000)
    page.evaluate(HOOK_JS)
    return ids


def drag_positions() -> list[int]:
    """The drag's slider positions: over 2/3 of the slider and back, DRAG_HZ a second for
    DRAG_SECONDS (positions the single moves do not use)."""
    n = int(DRAG_HZ * DRAG_SECONDS)
    lo, hi = 120, 880
    return [round(lo + (hi - lo) * (1 - abs(1 - 2 * k / (n - 1)))) + 1 for k in range(n)]


def measure(page, url: str, moves: int, first: int) -> dict:
    cdp = page.context.new_cdp_session(page)
    cdp.send("Performance.enable")
    ids = open_page(page, url)
    # α slider positions, each used once in the run: no answer comes from a cache
    positions = [first + 3 * i for i in range(moves + 3)]
    page.evaluate(MOVES_JS, [positions[:3], ids])          # warm
    cpu0 = thread_ms(cdp)
    res = page.evaluate(MOVES_JS, [positions[3:], ids])
    cpu_move = (thread_ms(cdp) - cpu0) / len(res)
    ms = [r["ms"] for r in res if r["ms"] == r["ms"]]
    per_panel = {i.removeprefix("plot-"): round(common.median([r["drawn"][i] for r in res if i in r["drawn"]]), 1)
                 for i in ids if any(i in r["drawn"] for r in res)}
    drag_pos = drag_positions()
    page.evaluate(MOVES_JS, [drag_pos[:1], ids])          # the hand takes the thumb there
    cpu0, threads0 = thread_ms(cdp), _threads()
    drag = page.evaluate(DRAG_JS, [drag_pos, ids, DRAG_HZ])
    cpu_drag, machine = thread_ms(cdp) - cpu0, contention(threads0, _threads())
    handled = drag["handled"]
    # each late event: how long it waited for its turn (the main thread busy, or waiting for
    # a CPU) and how long its own handler ran
    late = [[round(w, 1), round(h, 1)] for (w, h), t in zip(drag["split"], handled) if t > LATE_MS]
    return {"median_ms": round(common.median(ms), 1) if ms else float("nan"), "p95_ms": _pct(ms, 95),
            "moves": len(ms), "missed": len(res) - len(ms), "in_view": [i.removeprefix("plot-") for i in ids],
            "per_panel_median_ms": per_panel,
            "drag_redraws_per_s": {k.removeprefix("plot-"): round(v, 1) for k, v in drag["rates"].items()},
            "drag_settle_ms": round(drag["settle_ms"], 1),
            "drag_input_p95_ms": _pct(handled, 95), "drag_input_max_ms": round(max(handled), 1),
            "drag_input_over_16ms": sum(h > LATE_MS for h in handled), "drag_events": len(handled),
            "drag_late_waited_ran_ms": late,
            "drag_seconds": round(drag["seconds"], 2),
            "cpu_ms_per_move": round(cpu_move, 1), "drag_cpu_ms_per_event": round(cpu_drag / len(handled), 1),
            **{f"drag_{k}": v for k, v in machine.items()}}


def run(quick: bool = False, static: str | None = None) -> dict:
    from playwright.sync_api import sync_playwright
    moves = 12 if quick else 50
    out: dict = {"slider_viewport": f"{VIEWPORT['width']}x{VIEWPORT['height']}"}
    env = {"BRDF_STATIC_DIR": static} if static else None
    with common.server(env) as base, sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            page = browser.new_context(viewport=VIEWPORT).new_page()
            page.goto(base + "/")
            page.wait_for_function("() => window.__brdf && window.__brdf.pending() === 0", timeout=60_000)
            every = page.evaluate("() => window.__brdf.panels().map((p) => p.name)")
            common.log(f"  {base}: default page, then every panel; {moves} moves and a "
                       f"{DRAG_SECONDS:g} s drag at {DRAG_HZ} Hz each ...")
            out["slider_loadavg"] = [common.loadavg()]
            default = measure(page, base + "/", moves, first=200)
            out["slider_loadavg"].append(common.loadavg())
            full = measure(page, base + "/?show=" + ",".join(every), moves, first=200 + 3 * (moves + 5))
            out["slider_loadavg"].append(common.loadavg())
        finally:
            browser.close()
    for key, r in (("", default), ("_all_panels", full)):
        for k, v in r.items():
            out[f"slider{key}_{k}"] = v
    return out


def report(r: dict) -> list[str]:
    lines = [f"slider → pixels (α), headless Chromium {r['slider_viewport']}; load average "
             + " → ".join(str(x) for x in r["slider_loadavg"])]
    for key, label in (("", "default page"), ("_all_panels", "every panel")):
        g = lambda k: r[f"slider{key}_{k}"]  # noqa: E731
        lines.append(f"  {label}: input → last panel in view redrawn: median {g('median_ms')} ms, "
                     f"p95 {g('p95_ms')} ms over {g('moves')} moves ({g('missed')} missed); "
                     f"in view: {', '.join(g('in_view'))}")
        lines.append(f"      page main-thread CPU: {g('cpu_ms_per_move')} ms a move, "
                     f"{g('drag_cpu_ms_per_event')} ms an event of the drag")
        lines.append("      per panel, median ms: " + ", ".join(f"{k} {v}" for k, v in g("per_panel_median_ms").items()))
        lines.append(f"      drag {DRAG_HZ} Hz × {DRAG_SECONDS:g} s: redraws/s "
                     + ", ".join(f"{k} {v}" for k, v in g("drag_redraws_per_s").items())
                     + f"; settle {g('drag_settle_ms')} ms; input handled p95 {g('drag_input_p95_ms')} ms, "
                     f"max {g('drag_input_max_ms')} ms, {g('drag_input_over_16ms')} of {g('drag_events')} over 16.7 ms "
                     f"(the drag took {g('drag_seconds')} s)")
        if g("drag_late_waited_ran_ms"):
            lines.append("      late events, ms waited for their turn / their handler ran: "
                         + ", ".join(f"{w} / {h}" for w, h in g("drag_late_waited_ran_ms")))
        if r.get(f"slider{key}_drag_cpu_ms") is not None:
            lines.append(f"      during the drag: Chromium and the server {g('drag_cpu_ms')} ms of CPU; the page's "
                         f"main thread {g('drag_main_run_ms')} ms on a CPU, {g('drag_main_wait_ms')} ms "
                         "runnable but waiting for one")
    return lines


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--quick", action="store_true", help="12 moves instead of 50")
    ap.add_argument("--static", help="serve this static/ directory instead of the checkout's")
    args = ap.parse_args()
    print("\n".join(report(run(quick=args.quick, static=args.static))))
