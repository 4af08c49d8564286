"""Seconds per call of the checks view (app/checks.py, all rows), median of REPEATS,
in-process (no HTTP): the default model and the worst case over every NDF at α = 1e-4
and 1, isotropic and anisotropic (1e-4 : 1 and 1 : 1e-4), views at θ = 60° and 89.9°.

    python bench/checks.py              # default and the worst case (~1 min)

Each model is called once before timing (compiled kernels and tables are warm: the
first call of a process pays their compilation, reported separately as "cold").
"""
from __future__ import annotations

import statistics
import time

import common  # noqa: F401  (puts the checkout on sys.path)

from app.analysis.checks import checks
from app.errors import ParameterError
from app.model import make_spec
from app.physics.ndf import NDFS

REPEATS = 20


def seconds(spec, theta: float, repeats: int = REPEATS) -> tuple[float, float]:
    t0 = time.perf_counter()
    checks(spec, theta)
    cold = time.perf_counter() - t0
    times = []
    for _ in range(repeats):
        t0 = time.perf_counter()
        checks(spec, theta)
        times.append(time.perf_counter() - t0)
    return statistics.median(times), cold


def main() -> None:
    default = make_spec(ndf="ggx", alpha=0.3)
    med, cold = seconds(default, 60.0)
    print(f"default GGX α=0.3, θ=60°: median {med * 1e3:.1f} ms of {REPEATS} (first call {cold * 1e3:.0f} ms)")
    results = []
    for ndf in NDFS:
        for ax, ay in ((1e-4, None), (1.0, None), (1e-4, 1.0), (1.0, 1e-4)):
            try:
                spec = make_spec(ndf=ndf, alpha=ax, alpha_y=ay)
            except ParameterError:
                continue                    # isotropic-only NDF
            for theta in (60.0, 89.9):
                med, cold = seconds(spec, theta, 5)
                results.append((med, cold, ndf, ax, ay, theta))
                common.log(f"{ndf} α=({ax:g}, {ay if ay is None else f'{ay:g}'}) θ={theta:g}°: "
                           f"{med * 1e3:.1f} ms (first {cold * 1e3:.0f} ms)")
    results.sort(reverse=True)
    print("slowest (median of 5, then of 20):")
    for med, cold, ndf, ax, ay, theta in results[:3]:
        spec = make_spec(ndf=ndf, alpha=ax, alpha_y=ay)
        med20, _ = seconds(spec, theta)
        print(f"  {ndf} α=({ax:g}, {ay}) θ={theta:g}°: median {med20 * 1e3:.1f} ms of {REPEATS}"
              f" (first call {cold * 1e3:.0f} ms)")


if __name__ == "__main__":
    main()
