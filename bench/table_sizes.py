"""E(μ, α) table: size against measured error and build time (issue 4's "table at
≤ 1e-5"). For each size n×n, builds the F = 1 table of one NDF (default GGX,
height-correlated Smith) and reports its error three ways: the build's own reported
bound, the largest deviation it saw at its check points, and an independent dense
check (the quadrature at tol 1e-8 on 15 roughness values × 80 cosines the build never
used, including μ ~ α near grazing and μ → 0 at α → 1, the hardest corner).

    python bench/table_sizes.py [ndf] [sizes...]      e.g.  python bench/table_sizes.py ggx 32 48 64
"""
from __future__ import annotations

import sys
import time

import numpy as np

sys.path.insert(0, ".")
from app.integrate import tables  # noqa: E402
from app.integrate.albedo import albedo  # noqa: E402
from app.model import make_spec  # noqa: E402


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


def main() -> None:
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
