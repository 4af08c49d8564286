"""Slider to pixels: headless Chromium (Debian's, driven by Playwright) on the real app.

For each of N moves of the α slider: the time from the slider's `input` event to the
last `plotly_afterplot` among the panels that redraw for it (every shown panel depends on
α), taken once the page is quiet again (window.__brdf.pending() = 0). Reported: median
and p95, for the default page and for the page with every panel shown (?show=<all>),
at 1280 × 800 like the browser tests. Between moves the page is let go quiet, so each
move is measured alone (the coalescing of fast moves is tested in tests/e2e).
"""
from __future__ import annotations

import os

import common  # first: puts the checkout on sys.path

CHROMIUM = os.environ.get("BRDF_CHROMIUM", "/usr/bin/chromium")
CHROMIUM_ARGS = ["--no-sandbox", "--disable-gpu", "--disable-background-networking",
                 "--disable-component-update", "--disable-sync", "--no-first-run"]
VIEWPORT = {"width": 1280, "height": 800}

QUIET_JS = """() => window.__brdf && window.__brdf.pending() === 0
    && window.__brdf.panels().filter((p) => p.visible).every((p) => p.drawn || p.error)"""

# Runs in the page: moves the slider, collects plotly_afterplot per plot div.
MOVES_JS = """async ([positions, sliderId]) => {
  const slider = document.getElementById(sliderId);
  const events = [];
  const hooked = new Set();
  const hook = () => {
    for (const d of document.querySelectorAll('.js-plotly-plot')) {
      if (hooked.has(d) || typeof d.on !== 'function') continue;
      hooked.add(d);
      d.on('plotly_afterplot', () => events.push([d.id, performance.now()]));
    }
  };
  const sleep = (ms) => new Promise((r) => setTimeout(r, ms));
  const out = [];
  for (const pos of positions) {
    hook();
    events.length = 0;
    const t0 = performance.now();
    slider.value = String(pos);
    slider.dispatchEvent(new Event('input', { bubbles: true }));
    // quiet: nothing pending, and no afterplot for 60 ms
    const deadline = t0 + 20000;
    for (;;) {
      await sleep(5);
      const now = performance.now();
      const last = events.length ? events[events.length - 1][1] : t0;
      if (window.__brdf.pending() === 0 && now - last > 60) break;
      if (now > deadline) break;
    }
    const after = events.filter((e) => e[1] >= t0);
    const fetches = performance.getEntriesByType('resource')
      .filter((e) => e.startTime >= t0 && e.name.includes('/api/v1/'))
      .map((e) => [new URL(e.name).pathname.split('/').pop(), e.startTime - t0, e.responseEnd - t0,
                   e.transferSize, e.decodedBodySize]);
    const drawn = {};
    for (const [id, t] of after) drawn[id.replace(/^plot-/, '')] = t - t0;
    out.push({ ms: after.length ? Math.max(...after.map((e) => e[1])) - t0 : NaN,
               panels: new Set(after.map((e) => e[0])).size, fetches, drawn });
    performance.clearResourceTimings();
  }
  return out;
}"""


# Runs in the page: for each shown panel, its figure fetched once, then Plotly.react
# with it (fresh objects each time, so Plotly redoes the work) — the main-thread cost
# of drawing that panel, without the network and without the other panels.
DRAW_JS = """async ([names, repeat]) => {
  const out = {};
  for (const name of names) {
    const div = document.getElementById('plot-' + name);
    const url = window.__brdf.url(name);
    if (!div || !url || !div.layout) continue;
    const text = await (await fetch(url, { headers: { Accept: 'application/json' } })).text();
    const ts = [];
    for (let k = 0; k < repeat; k++) {
      const t0 = performance.now();
      const body = JSON.parse(text);
      await Plotly.react(div, body.data, { ...div.layout });
      ts.push(performance.now() - t0);
    }
    ts.sort((a, b) => a - b);
    out[name] = ts[Math.floor(ts.length / 2)];
  }
  return out;
}"""


def measure(page, url: str, moves: int, first: int) -> dict:
    page.goto(url)
    page.wait_for_function(QUIET_JS, timeout=60_000)
    shown = page.evaluate("() => window.__brdf.panels().filter((p) => p.visible).map((p) => p.name)")
    # α slider positions, each used once in the run (slider ticks ``first``, first + 3,
    # ...): no response can come from the browser's HTTP cache
    positions = [first + 3 * i for i in range(moves + 3)]
    page.evaluate(MOVES_JS, [positions[:3], "alpha-slider"])          # warm
    page.wait_for_function(QUIET_JS, timeout=60_000)
    res = page.evaluate(MOVES_JS, [positions[3:], "alpha-slider"])
    ms = [r["ms"] for r in res if r["ms"] == r["ms"]]
    # per panel: median fetch start, response end and afterplot, ms after the input event
    breakdown = {}
    for name in shown:
        starts = [f[1] for r in res for f in r["fetches"] if f[0] == name]
        ends = [f[2] for r in res for f in r["fetches"] if f[0] == name]
        drawn = [r["drawn"][name] for r in res if name in r["drawn"]]
        wire = [f[3] for r in res for f in r["fetches"] if f[0] == name]
        body = [f[4] for r in res for f in r["fetches"] if f[0] == name]
        if drawn:
            breakdown[name] = {
                "fetch_start_ms": round(common.median(starts), 1) if starts else None,
                "response_end_ms": round(common.median(ends), 1) if ends else None,
                "afterplot_ms": round(common.median(drawn), 1),
                "bytes_wire": int(common.median(wire)) if wire else None,
                "bytes_body": int(common.median(body)) if body else None}
    page.wait_for_function(QUIET_JS, timeout=60_000)
    draw = page.evaluate(DRAW_JS, [shown, 7])
    for name, ms_draw in draw.items():
        breakdown.setdefault(name, {})["draw_alone_ms"] = round(ms_draw, 1)
    return {"breakdown": breakdown, "draw_sum_ms": round(sum(draw.values()), 1),"median_ms": common.median(ms) if ms else float("nan"),
            "p95_ms": common.percentile(ms, 95),
            "moves": len(ms), "missed": len(res) - len(ms),
            "panels_shown": shown,
            "panels_redrawn_median": common.median([r["panels"] for r in res])}


def run(quick: bool = False) -> dict:
    from playwright.sync_api import sync_playwright
    moves = 12 if quick else 50
    out: dict = {}
    with common.server() as base, sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS, headless=True)
        try:
            page = browser.new_context(viewport=VIEWPORT).new_page()
            page.goto(base + "/")
            page.wait_for_function(QUIET_JS, timeout=60_000)
            every = page.evaluate("() => window.__brdf.panels().map((p) => p.name)")
            common.log(f"  {base}: default page, then every panel ({', '.join(every)}); "
                       f"{moves} moves each ...")
            out["slider_loadavg"] = [common.loadavg()]
            default = measure(page, base + "/", moves, first=200)
            full = measure(page, base + "/?show=" + ",".join(every), moves, first=200 + 3 * (moves + 5))
            out["slider_loadavg"].append(common.loadavg())
        finally:
            browser.close()
    for key, r in (("", default), ("_all_panels", full)):
        out[f"slider{key}_median_ms"] = r["median_ms"]
        out[f"slider{key}_p95_ms"] = r["p95_ms"]
        out[f"slider{key}_moves"] = r["moves"]
        out[f"slider{key}_missed"] = r["missed"]
        out[f"slider{key}_panels"] = r["panels_shown"]
        out[f"slider{key}_panels_redrawn"] = r["panels_redrawn_median"]
        out[f"slider{key}_breakdown"] = r["breakdown"]
        out[f"slider{key}_draw_sum_ms"] = r["draw_sum_ms"]
    return out


def report(r: dict) -> list[str]:
    lines = ["slider → pixels (α slider input → last plotly_afterplot), headless Chromium 1280×800; "
             f"load average {r['slider_loadavg'][0]} → {r['slider_loadavg'][-1]}"]
    for key, label in (("", "default page"), ("_all_panels", "every panel")):
        lines.append(f"  {label:13s}: median {r[f'slider{key}_median_ms']:6.1f} ms, p95 "
                     f"{r[f'slider{key}_p95_ms']:6.1f} ms over {r[f'slider{key}_moves']} moves; "
                     f"{r[f'slider{key}_panels_redrawn']:g} panels redrawn per move "
                     f"({', '.join(r[f'slider{key}_panels'])})")
        lines.append(f"      JSON.parse + Plotly.react of every shown panel, one after another, "
                     f"alone: {r[f'slider{key}_draw_sum_ms']} ms")
        for name, b in r[f"slider{key}_breakdown"].items():
            lines.append(f"      {name:8s} fetch {b.get('fetch_start_ms')}→{b.get('response_end_ms')} ms, "
                         f"drawn at {b.get('afterplot_ms')} ms (draw alone {b.get('draw_alone_ms')} ms); "
                         f"{b.get('bytes_body')} B ({b.get('bytes_wire')} B on the wire)")
    return lines


if __name__ == "__main__":
    print("\n".join(report(run(quick=True))))
