"""The GPU panel's environment sphere (static/js/gpu/env.js) while the light is dragged
and at rest, with its coarse preview off and on in the same run (same page, same models).

While dragging: the environment sphere's frames per second (its frames drawn during the
drag over the drag's duration) and its input-to-frame (from the pointer event's timeStamp
to the environment frame that first used it, finished: a one-pixel read back), and the
point-lit sphere's input-to-frame beside it (both draw in the one SwiftShader GPU process).
At rest (after the drag, full size): the noise as the panel states it (render.py's
``noise.relative``: each pixel's standard error, RMS over the disk, over the mean) at
2 s, the seconds until it is at or below the server's at 16 samples a pixel (n = 256) and
until ≤ 5 %.

    python bench/gpu_env.py [--moves 30] [--envs studio,sunset] [--rest 20] [--models 2] [--json]
"""
from __future__ import annotations

import argparse
import json
import math
import os

import common  # first: puts the checkout on sys.path

from tests.live import running_server

CHROMIUM = os.environ.get("BRDF_CHROMIUM", "/usr/bin/chromium")
PAGE = "/?show=gpu&alpha=0.3&kd=0.3&theta_i_deg=40&phi_i_deg=135"
MODELS = [{"ndf": "ggx", "alpha": 0.3, "kd": 0.3}, {"model": "principled"}]
NOISE_GOAL = 0.05


def drag(page, moves: int) -> dict:
    """One circle of `moves` pointer moves on the GPU sphere; the panel's timings."""
    box = page.locator("#gpu-canvas").bounding_box()
    cx, cy, r = box["x"] + box["width"] / 2, box["y"] + box["height"] / 2, box["width"] * 0.35
    page.evaluate("() => window.__gpu.clearTimings()")
    page.mouse.move(cx + r, cy)
    page.mouse.down()
    t0 = page.evaluate("() => performance.now()")
    for k in range(1, moves + 1):
        a = 2 * math.pi * k / moves
        page.mouse.move(cx + r * math.cos(a), cy + r * math.sin(a))
    t1 = page.evaluate("() => performance.now()")
    page.mouse.up()
    env_frames = [f["t"] for f in page.evaluate("() => window.__gpu.envFrames") if t0 <= f["t"] <= t1]
    return {"env_fps": len(env_frames) / ((t1 - t0) / 1000), "env_frames": len(env_frames),
            "env_input_to_frame_ms": common.median(page.evaluate("() => window.__gpu.envTimings")),
            "point_input_to_frame_ms": common.median(page.evaluate("() => window.__gpu.timings")),
            "drag_s": (t1 - t0) / 1000}


def rest(page, seconds: float) -> dict:
    """After the drag: the accumulation at full size, its noise history and the server's."""
    page.wait_for_function("() => !window.__gpu.envPreviewing && window.__gpu.env && window.__gpu.env.reference",
                           timeout=120_000, polling=250)
    page.wait_for_function(f"() => window.__gpu.env.seconds >= {seconds}", timeout=int(seconds * 1000) + 120_000,
                           polling=500)
    hist = page.evaluate("() => window.__gpu.envHistory")
    env = page.evaluate("() => window.__gpu.env")
    server = env["reference"]["relative"]
    at2 = [h for h in hist if h["seconds"] <= 2.0]
    first = lambda level: next((h["seconds"] for h in hist if h["relative"] <= level), None)  # noqa: E731
    return {"noise_at_2s": at2[-1]["relative"] if at2 else None, "pairs_at_2s": at2[-1]["samples"] if at2 else 0,
            "server_noise_16spp": server, "s_to_server_noise": first(server), "s_to_5pct": first(NOISE_GOAL),
            "noise_at_end": hist[-1]["relative"], "seconds_at_end": hist[-1]["seconds"],
            "pairs_per_s": hist[-1]["samples"] / hist[-1]["seconds"]}


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    ap.add_argument("--moves", type=int, default=30)
    ap.add_argument("--envs", default="studio,sunset")
    ap.add_argument("--rest", type=float, default=20.0, help="seconds of rest measured after the drag")
    ap.add_argument("--models", type=int, default=len(MODELS), help="the first this many of MODELS")
    ap.add_argument("--json", action="store_true")
    args = ap.parse_args()
    from playwright.sync_api import sync_playwright

    rows = []
    load = os.getloadavg()
    with running_server() as (url, _), sync_playwright() as pw:
        browser = pw.chromium.launch(executable_path=CHROMIUM, args=["--no-sandbox", "--disable-gpu"])
        page = browser.new_page(viewport={"width": 1280, "height": 900})
        page.on("console", lambda msg: msg.type == "error" and common.log(f"console: {msg.text}"))
        page.on("pageerror", lambda err: common.log(f"page error: {err}"))
        page.goto(url + PAGE)
        page.wait_for_function("() => window.__gpu && window.__gpu.ok", timeout=60000)
        for m in MODELS[:args.models]:
            page.evaluate("(m) => window.__gpu.load(m)", m)
            for env in args.envs.split(","):
                page.evaluate("(e) => window.__gpu.setEnvironment(e)", env)
                for preview in (False, True):
                    page.evaluate("(on) => { window.__gpu.envPreview = on; }", preview)
                    row = {"model": m, "environment": env, "preview": preview, **drag(page, args.moves)}
                    if preview:
                        row.update(rest(page, args.rest))
                    rows.append(row)
                    common.log(json.dumps(row))
        browser.close()
    summary = {"load_before": load, "load_after": os.getloadavg(), "moves": args.moves}
    for preview in (False, True):
        sel = [r for r in rows if r["preview"] == preview]
        key = "preview" if preview else "full_size"
        summary[key] = {k: common.median([r[k] for r in sel]) for k in
                        ("env_fps", "env_input_to_frame_ms", "point_input_to_frame_ms")}
    print(json.dumps({"summary": summary, "rows": rows} if args.json else summary, indent=1))


if __name__ == "__main__":
    main()
