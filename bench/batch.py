"""The server's part of a slider move: POST /api/v1/batch of the default page's four
figures (lobe, D, G1, albedo), in process through the ASGI application, answered as the
batch does (each figure by its route's steps, in one worker thread) and, alternated in
the same run, as four GETs through the whole application each (what it did before).

``python bench/batch.py [N] [--gap MS]``: N batches of each (default 300), alternated, α
moved a little each time (nothing cached); ``--gap`` waits that long between batches, as
a slider's moves come apart (default 0: back to back). Prints the medians and p10s, ms.
"""
from __future__ import annotations

import argparse
import asyncio
import json
import statistics

import common  # noqa: F401  (puts the checkout on sys.path)

from app.api import routes_batch
from app.main import create_app

QUERY = ("ndf=ggx&masking=smith&g2=height_correlated&fresnel=schlick&multiscatter=none"
         "&diffuse=lambert&alpha={a}&kd=0&f0=0.04&f90=1&fresnel_p=5")
FIGURES = [f"/api/v1/figures/lobe?{QUERY}&theta_i_deg=45&phi_i_deg=0",
           f"/api/v1/figures/ndf?{QUERY}", f"/api/v1/figures/g1?{QUERY}",
           f"/api/v1/figures/albedo?{QUERY}&method=auto"]
#: the start-up tables and compiled loops load in the background first
WARM_UP_S = 8.0


async def _post(app, body: bytes) -> bytes:
    scope = {"type": "http", "asgi": {"version": "3.0"}, "http_version": "1.1", "method": "POST",
             "scheme": "http", "path": "/api/v1/batch", "raw_path": b"/api/v1/batch",
             "root_path": "", "query_string": b"", "client": ("127.0.0.1", 1),
             "server": ("127.0.0.1", 8000),
             "headers": [(b"host", b"127.0.0.1"), (b"content-type", b"application/json"),
                         (b"content-length", str(len(body)).encode())]}
    messages = [{"type": "http.request", "body": body, "more_body": False}]
    out = []

    async def receive():
        return messages.pop() if messages else {"type": "http.disconnect"}

    async def send(message):
        out.append(message)

    await app(scope, receive, send)
    assert out[0]["status"] == 200, out[0]
    answers = json.loads(b"".join(m.get("body", b"") for m in out[1:]))["responses"]
    assert all(a["status"] == 200 for a in answers), answers
    return answers


async def main(n: int, gap_ms: float) -> dict:
    app = create_app()
    direct = dict(routes_batch.FIGURE_GETS)
    times = {"by the route's steps": [], "four GETs through the app": []}
    async with app.router.lifespan_context(app):
        await asyncio.sleep(WARM_UP_S)
        loop = asyncio.get_running_loop()
        for k in range(2 * n + 20):
            mode = list(times)[k % 2]
            # the batch answers through the whole application what FIGURE_GETS lacks
            routes_batch.FIGURE_GETS.clear()
            if k % 2 == 0:
                routes_batch.FIGURE_GETS.update(direct)
            body = json.dumps({"requests": [u.format(a=0.2 + 1e-5 * k) for u in FIGURES]}).encode()
            if gap_ms:
                await asyncio.sleep(gap_ms / 1000)
            t0 = loop.time()
            await _post(app, body)
            if k >= 20:                      # the first few warm the paths up
                times[mode].append(1000 * (loop.time() - t0))
    routes_batch.FIGURE_GETS.update(direct)
    return {mode: (statistics.median(ts), sorted(ts)[len(ts) // 10]) for mode, ts in times.items()}


if __name__ == "__main__":
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("n", nargs="?", type=int, default=300)
    ap.add_argument("--gap", type=float, default=0.0, help="ms between batches")
    args = ap.parse_args()
    for mode, (median, p10) in asyncio.run(main(args.n, args.gap)).items():
        print(f"{mode:28s} median {median:6.2f} ms   p10 {p10:6.2f} ms")
