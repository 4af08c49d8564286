"""First answer of Kulla-Conty's albedo for a shape the server has never seen (issue 37).

One server per round with an empty BRDF_CACHE_DIR; for each NDF shape of issue 37's table,
the ends of each declared shape range (GTR γ 0.5/10, exp_power p 0.25/0.3/3/4, Student-t
γ from the first double above its open lower limit 1.5, and 1000), and values never used
before (derived from the clock: GTR γ in [1, 2), Student-t γ just above 1.5, in
[1.52, 1.53] and in [2, 1000], exp_power p near 0.3 and near 3), time
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
          "ndf=exp_power&p=2.0", "ndf=exp_power&p=1.763",
          "ndf=gtr&gamma=0.5", "ndf=gtr&gamma=10", "ndf=student_t&gamma=1.5000000000000002",
          "ndf=student_t&gamma=1.52",
          "ndf=student_t&gamma=1000", "ndf=exp_power&p=0.25", "ndf=exp_power&p=0.3",
          "ndf=exp_power&p=3.0", "ndf=exp_power&p=4.0"]


def fresh_shapes() -> list[str]:
    """Shape values no earlier round (or run) asked for: from the clock's nanoseconds."""
    f = (time.time_ns() % 997) / 997.0
    return [f"ndf=gtr&gamma={1.0 + f:.6f}", f"ndf=student_t&gamma={1.5 + 0.001 * f:.9f}",
            f"ndf=student_t&gamma={1.52 + 0.01 * f:.6f}", f"ndf=student_t&gamma={2.0 + 998.0 * f:.4f}",
            f"ndf=exp_power&p={0.3 + 0.01 * f:.6f}", f"ndf=exp_power&p={3.0 - 0.01 * f:.6f}"]


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
        with tempfile.TemporaryDirectory() as cache, common.server({"BRDF_CACHE_DIR": cache}) as url:
            print(f"round {r + 1}, load {common.loadavg()}")
            for shape in SHAPES + fresh_shapes():
                res = first_answer(url, base + shape)
                print(f"  {shape:24s} {json.dumps(res)}", flush=True)


if __name__ == "__main__":
    main()
