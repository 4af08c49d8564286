"""Summarising a samples CSV: seconds against rows, as a ratio (issue 36: 870 000 rows
kept a core busy > 10 min; the grouping was O(groups × rows)).

Two shapes of file at n = N/16, N/4, N rows (N = 870 000): "distinct" (every row its own
random view and light direction: n groups of one) and "grid" (√n-ish view directions,
each with the rest as random light directions: few large groups, each triangulated).
Prints the median seconds of ``rounds`` runs of formats.load + summary.summarize (parse
apart), and t(n)/t(n/4) — ~4–5 for O(n log n), ~16 for O(n²).

    python bench/data_summary.py [--rows 870000] [--rounds 3]
"""
from __future__ import annotations

import argparse
import io
import statistics
import time

import common  # noqa: F401  first: puts the checkout on sys.path
import numpy as np

from app.datasets import formats, summary

HEADER = "theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f"


def _csv(n: int, shape: str, seed: int = 0) -> bytes:
    rng = np.random.default_rng(seed)
    ti = np.degrees(np.arccos(np.sqrt(rng.uniform(0, 1, n))))
    pi = rng.uniform(0, 360, n)
    if shape == "distinct":
        to, po = rng.uniform(0, 89, n), rng.uniform(0, 360, n)
    else:
        views = max(1, int(np.sqrt(n)))
        k = rng.integers(0, views, n)
        to, po = (k * 89.0 / views).round(4), (k * 7.0 % 360).round(4)
    f = rng.uniform(0.01, 3.0, n)
    out = io.StringIO()
    np.savetxt(out, np.column_stack([ti, pi, to, po, f]), delimiter=",", fmt="%.6f", header=HEADER,
               comments="")
    return out.getvalue().encode()


def main() -> None:
    parser = argparse.ArgumentParser()
    parser.add_argument("--rows", type=int, default=870_000)
    parser.add_argument("--rounds", type=int, default=3)
    args = parser.parse_args()
    for shape in ("distinct", "grid"):
        times = {}
        for n in (args.rows // 16, args.rows // 4, args.rows):
            content = _csv(n, shape)
            parse, summ = [], []
            for _ in range(args.rounds):
                t0 = time.perf_counter()
                data = formats.load(content)
                t1 = time.perf_counter()
                info = summary.summarize(data)
                summ.append(time.perf_counter() - t1)
                parse.append(t1 - t0)
            times[n] = statistics.median(summ)
            print(f"{shape:9s} n={n:8d} ({len(content) / 1e6:5.1f} MB): parse {statistics.median(parse):6.2f} s, "
                  f"summary {times[n]:6.2f} s, {len(info['albedo']['mu'])} directions integrated", flush=True)
        ns = sorted(times)
        for a, b in zip(ns, ns[1:]):
            print(f"{shape:9s} t({b})/t({a}) = {times[b] / times[a]:.2f} (rows ×{b / a:.0f})")


if __name__ == "__main__":
    main()
