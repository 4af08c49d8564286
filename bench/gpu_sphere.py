"""The live GPU sphere (static/js/gpu/) under a point light: input-to-frame while the
light is dragged with the mouse, for every registry model (tests/shader/models.py's
list: each NDF × masking × G2, each Fresnel, λ(φ), anisotropy, two lobes, Kulla-Conty,
materials) and for the principled BRDF when /api/v1/code writes it.

Input-to-frame: from the pointermove's timeStamp (when the input happened) to the frame
drawn and finished (a one-pixel read back), measured in the page; a 256² sphere; the
mouse moved by Playwright (CDP input, each move awaited) in a circle on the sphere.
Headless Debian Chromium, WebGL2 on SwiftShader (the CPU). One page load; each model is
loaded into the GPU panel by its query (window.__gpu.load), which compiles it once.

    python bench/gpu_sphere.py [--moves 40] [--json]
"""
from __future__ import annotations

import argparse
import json
import math
import os

import common  # first: puts the checkout on sys.path

from tests.live import running_server
from tests.shader.models import registry_models

CHROMIUM = os.environ.get("BRDF_CHROMIUM", "/usr/bin/chromium")
#: 60 frames/s
BUDGET_MS = 1000.0 / 60.0
PRINCIPLED = {"model": "principled"}


def drag(page, moves: int) -> list[float]:
    box = page.locator("#gpu-canvas").bounding_box()
    cx, cy, r = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2, box["width"] * 0.35
    page.evaluate("() => window.__gpu.clearTimings()")
    page.mouse.move(cx + r, cy)
    page.mouse.down()
    for k in range(moves):
        a = 2 * math.pi * k / moves
        page.mouse.move(cx + r * math.cos(a), cy + r * math.sin(a))
    page.mouse.up()
    page.wait_for_timeout(50)
    return page.evaluate("() => window.__gpu.timings")


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--moves", type=int, default=40)
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    models = registry_models() + [PRINCIPLED]
    rows = []
    load = os.getloadavg()
    with running_server() as (url, _), sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox", "--disable-gpu"])
        page = browser.new_page(viewport={"width": 1280, "height": 900})
        page.goto(url + "/?show=gpu")
        page.wait_for_function("() => window.__gpu && window.__gpu.ok", timeout=60000)
        for m in models:
            message = page.evaluate("(m) => window.__gpu.load(m)", m)
            ok = page.evaluate("() => window.__gpu.ok")
            if not ok:
                rows.append({"model": m, "error": message})
                common.log(f"{json.dumps(m)}: no GPU view: {message}")
                continue
            times = drag(page, args.moves)
            row = {"model": m, "frames": len(times), "median_ms": common.median(times),
                   "p90_ms": common.percentile(times, 90), "max_ms": max(times)}
            rows.append(row)
            common.log(f"{json.dumps(m)}: median {row['median_ms']:.2f} ms, p90 {row['p90_ms']:.2f} ms "
                       f"({row['frames']} frames)")
        browser.close()
    drawn = [r for r in rows if "error" not in r]
    worst = max(drawn, key=lambda r: r["median_ms"])
    summary = {"load_before": load, "load_after": os.getloadavg(), "models": len(models), "drawn": len(drawn),
               "within_16.7ms": sum(r["median_ms"] <= BUDGET_MS for r in drawn),
               "worst_median_ms": worst["median_ms"], "worst_model": worst["model"],
               "median_of_medians_ms": common.median([r["median_ms"] for r in drawn]),
               "not_drawn": [{"model": r["model"], "why": r["error"]} for r in rows if "error" in r]}
    if args.json:
        print(json.dumps({"summary": summary, "rows": rows}, indent=1))
    else:
        print(json.dumps(summary, indent=1))


if __name__ == "__main__":
    main()
