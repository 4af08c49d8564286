"""First answer of Kulla-Conty's albedo for a shape the server has never seen (issue 37).

One server per round with an empty BRDF_CACHE_DIR; for each NDF shape of issue 37's table
(plus a γ never used before, derived from the clock), time
``GET /api/v1/albedo?alpha=0.37&fresnel=none&multiscatter=kulla_conty&n=9&ndf=…`` to its
200, following each 503's Retry-After as documented; report the time, the 503s and their
Retry-After, and the stated ``compensation_error``.

    python bench/cold_shapes.py [rounds]
"""
from __future__ import annotations

import json
import sys
import tempfile
import time
import urllib.error
import urllib.request

import common  # first: puts the checkout on sys.path

SHAPES = ["ndf=ggx", "ndf=beckmann", "ndf=gtr&gamma=1.0", "ndf=gtr&gamma=1.05",
          "ndf=gtr&gamma=1.2", "ndf=gtr&gamma=1.5", "ndf=student_t&gamma=1.6",
          "ndf=exp_power&p=2.0", "ndf=exp_power&p=1.763"]


def first_answer(url: str, query: str) -> dict:
    t0 = time.perf_counter()
    retries = []
    while True:
        try:
            with urllib.request.urlopen(f"{url}/api/v1/albedo?{query}", timeout=60) as res:
                body = json.loads(res.read())
            return {"seconds": time.perf_counter() - t0, "retries": retries,
                    "compensation_error": body.get("compensation_error")}
        except urllib.error.HTTPError as exc:
            if exc.code != 503:
                return {"seconds": time.perf_counter() - t0, "status": exc.code}
            wait = float(exc.headers.get("Retry-After", "1"))
            retries.append(wait)
            time.sleep(wait)


def main() -> None:
    rounds = int(sys.argv[1]) if len(sys.argv) > 1 else 1
    base = "alpha=0.37&fresnel=none&multiscatter=kulla_conty&n=9&"
    for r in range(rounds):
        fresh = f"ndf=gtr&gamma={1.0 + (time.time_ns() % 997) / 1000.0:.3f}"
        with tempfile.TemporaryDirectory() as cache, common.server({"BRDF_CACHE_DIR": cache}) as url:
            print(f"round {r + 1}, load {common.loadavg()}")
            for shape in SHAPES + [fresh]:
                res = first_answer(url, base + shape)
                print(f"  {shape:24s} {json.dumps(res)}", flush=True)


if __name__ == "__main__":
    main()
