"""E(μ, α) tables: size against measured error and build time, and every NDF's build.

    python bench/table_sizes.py [ndf] [sizes...]   e.g. python bench/table_sizes.py ggx 32 48 64
    python bench/table_sizes.py --all [n] [rounds]  every NDF's n×n table (default 32), medians
    python bench/table_sizes.py --first-kc           a fresh server per NDF: its first Kulla-Conty request

Sizes: for each n×n, builds the F = 1 table of one NDF (height-correlated Smith) and
reports its error three ways: the build's own reported bound, the largest deviation it
saw at its check points, and an independent dense check (the quadrature at tol 1e-8 on
15 roughness values × 80 cosines the build never used, including μ ~ α near grazing
and μ → 0 at α → 1, the hardest corner).

--all: the build time of each NDF's n×n table (shape parameters at their defaults,
compiled loops loaded first, Smith Λ tables built afresh each round), median over rounds,
with its reported bound; the time and the load average before and after.

--first-kc: for each NDF, a new server (compiled loops in their cache, an empty table
cache directory), and its first GET /api/v1/albedo with multiscatter=kulla_conty
(Blinn-Phong with masking=smith_numeric): wall time to the first answer (a 503 — the
table is being built — is retried after its Retry-After, and counted) and the reported
compensation_error.
"""
from __future__ import annotations

import json
import os
import sys
import tempfile
import time
import urllib.error
import urllib.parse
import urllib.request

import numpy as np

import common  # first: puts the checkout on sys.path

from app import kernels  # noqa: E402
from app.integrate import tables  # noqa: E402
from app.integrate.albedo import albedo  # noqa: E402
from app.model import make_spec  # noqa: E402
from app.physics import lambda_table, smith_table  # noqa: E402
from app.physics.ndf import NDFS  # noqa: E402

#: the masking of each NDF's Kulla-Conty request: Blinn-Phong's own "smith" is an
#: approximation, so its compensation is asked with the Smith integral.
KC_MASKING = {"blinn_phong": "smith_numeric"}


def dense_error(table, ndf: str) -> float:
    rng = np.random.default_rng(99)
    worst = 0.0
    for r in np.concatenate([[0.012, 0.03, 0.07, 0.97, 0.99, 1.0], rng.uniform(0.01, 1.0, 9)]):
        alpha = r * r
        mu = np.concatenate([rng.uniform(0.0, 1.0, 40), np.geomspace(1e-6, 0.1, 30),
                             1.0 - np.geomspace(1e-6, 0.1, 10)])
        ref = albedo(make_spec(ndf=ndf, alpha=alpha, fresnel="none").brdf(), mu, tol=1e-8).E
        worst = max(worst, float(np.max(np.abs(table.E(mu, alpha) - ref))))
    return worst


def all_ndfs(n: int, rounds: int) -> None:
    # the machine is shared: CPU seconds are the comparable figure, the load says how far
    # the wall clock is from them
    print(f"{time.strftime('%H:%M UTC', time.gmtime())}, load average "
          f"{' '.join(f'{x:.1f}' for x in os.getloadavg())}", flush=True)
    print(f"| NDF | {n}×{n} build, wall s (median of {rounds}) | CPU s | reported bound | evaluations |")
    print("|---|---|---|---|---|")
    for name in NDFS:
        lobe = make_spec(ndf=name, alpha=0.3, fresnel="none", masking=KC_MASKING.get(name, "smith")).brdf()
        kernels.compile_now(lobe, "albedo")
        key = tables.table_key(lobe)
        times, cpu, table = [], [], None
        for _ in range(rounds):
            # each round builds its Smith Λ tables (GTR, Blinn-Phong: one per row) as a
            # first build does: the process-wide caches would serve rounds 2 and 3
            smith_table._table.cache_clear()
            lambda_table._packed.cache_clear()
            t0, c0 = time.perf_counter(), time.process_time()
            table = tables.build(key, n, n)
            times.append(time.perf_counter() - t0)
            cpu.append(time.process_time() - c0)
        print(f"| {name} | {common.median(times):.2f} ({', '.join(f'{t:.2f}' for t in times)}) | "
              f"{common.median(cpu):.2f} | {table.error:.1e} | {table.build_evaluations:.3g} |",
              flush=True)
    print(f"{time.strftime('%H:%M UTC', time.gmtime())}, load average "
          f"{' '.join(f'{x:.1f}' for x in os.getloadavg())}", flush=True)


def _answer(url: str) -> tuple[float, int, dict]:
    """Seconds from the first request to the first answer, the 503 (Busy: table being
    built) replies before it (each followed after its Retry-After), and the answer."""
    t0, busy = time.perf_counter(), 0
    while True:
        try:
            with urllib.request.urlopen(url, timeout=120) as res:
                return time.perf_counter() - t0, busy, json.loads(res.read())
        except urllib.error.HTTPError as exc:
            if exc.code != 503 or busy >= 20:
                raise
            busy += 1
            time.sleep(float(exc.headers.get("Retry-After", 1)))


def first_kc() -> None:
    print(f"{time.strftime('%H:%M UTC', time.gmtime())}, load average "
          f"{' '.join(f'{x:.1f}' for x in os.getloadavg())}", flush=True)
    print("| NDF | first Kulla-Conty answer, s | 503s before it | compensation_error | "
          "server's seconds |")
    print("|---|---|---|---|---|")
    for name in NDFS:
        query = {"ndf": name, "multiscatter": "kulla_conty", "fresnel": "none", "n": 17,
                 "masking": KC_MASKING.get(name, "smith")}
        # an empty table cache per server: a table persisted by an earlier run of the
        # same code would otherwise answer the "first" request
        with tempfile.TemporaryDirectory() as cache, \
                common.server(env={"BRDF_CACHE_DIR": cache}) as url:
            time.sleep(2.0)   # the server's background loading of its compiled loops
            seconds, busy, body = _answer(f"{url}/api/v1/albedo?{urllib.parse.urlencode(query)}")
        print(f"| {name} | {seconds:.2f} | {busy} | "
              f"{body.get('compensation_error', float('nan')):.1e} | {body.get('seconds', 0):.2f} |",
              flush=True)
    print(f"{time.strftime('%H:%M UTC', time.gmtime())}, load average "
          f"{' '.join(f'{x:.1f}' for x in os.getloadavg())}", flush=True)


def main() -> None:
    if sys.argv[1:2] == ["--all"]:
        all_ndfs(int(sys.argv[2]) if len(sys.argv) > 2 else 32,
                 int(sys.argv[3]) if len(sys.argv) > 3 else 3)
        return
    if sys.argv[1:2] == ["--first-kc"]:
        first_kc()
        return
    ndf = sys.argv[1] if len(sys.argv) > 1 else "ggx"
    sizes = [int(x) for x in sys.argv[2:]] or [16, 32, 48, 64]
    lobe = make_spec(ndf=ndf, alpha=0.3, fresnel="none").brdf()
    key = tables.table_key(lobe)
    albedo(lobe, [0.5])                     # compile the kernel outside the timings
    print(f"| {ndf} table | build s | evaluations | reported bound | seen at checks | dense check |")
    print("|---|---|---|---|---|---|")
    for n in sizes:
        t0 = time.perf_counter()
        table = tables.build(key, n, n)
        seconds = time.perf_counter() - t0
        print(f"| {n}×{n} | {seconds:.2f} | {table.build_evaluations:.3g} | {table.error:.2e} | "
              f"{table.measured:.2e} | {dense_error(table, ndf):.2e} |", flush=True)


if __name__ == "__main__":
    main()
