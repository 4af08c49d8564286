"""The trade-off table of the albedo methods, as GET /api/v1/tradeoff computes it.

For GGX α = 0.1 and α = 0.5 (height-correlated Smith, Schlick F₀ = 0.04: the page's
default model) at the view's 9 cosines μ = 0, 1/8, ..., 1: every method at every
budget, one markdown table per model — method, budget, evaluations, seconds (one run,
wall clock, this machine's load included), max over μ of |E − E_ref| and the method's
reported E_error (max over μ), the fraction of μ where the error is within the reported
one, and the reference's own bound and cost. An untimed warm-up first loads the
compiled kernels and builds the tables, whose build cost is printed.

    python bench/tradeoff.py [--max-budget 16384] [--seed 0]
"""
from __future__ import annotations

import argparse
import time

import common  # first: puts the checkout on sys.path

from app.analysis import tradeoff as to
from app.model import make_spec

MODELS = [{"ndf": "ggx", "alpha": 0.1}, {"ndf": "ggx", "alpha": 0.5}]


def markdown(data: dict, title: str) -> str:
    lines = [f"### {title}", "",
             f"Reference: quadrature to {to.REFERENCE_TOL:g}, bound {data['reference_error']:.1e}, "
             f"{data['reference_evaluations']} evaluations, {data['reference_seconds']:.3f} s. "
             f"Error = max over {data['mu_count']} μ of |E − E_ref|.", "",
             "| method | budget | evaluations | seconds | error vs reference | reported E_error "
             "| within reported |",
             "|---|---:|---:|---:|---:|---:|---:|"]
    for i, m in enumerate(data["method"]):
        lines.append(f"| {m} | {data['budget'][i]} | {data['evaluations'][i]} | "
                     f"{data['seconds'][i]:.4f} | {data['error'][i]:.2e} | "
                     f"{data['E_error'][i]:.2e} | {data['within_reported'][i]:.0%} |")
    if "table" in data:
        t = data["table"]
        lines += ["", f"Table ({t['size']} per table): build {t['build_evaluations']} evaluations, "
                      f"{t['build_seconds']:.2f} s (built in this run: {t['built_in_this_request']}); "
                      f"its reported bound {t['error']:.1e}."]
    return "\n".join(lines)


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--max-budget", type=int, default=to.DEFAULT_MAX_BUDGET)
    ap.add_argument("--seed", type=int, default=0)
    args = ap.parse_args()
    m = common.machine()
    print(f"{m['cpu']}, {m['nproc']} cores, 1-min load {common.loadavg()}; numpy {m['numpy']}, "
          f"numba {m['numba']}")
    # Warm-up, untimed: loads the compiled kernels and builds the tables (they depend on
    # the NDF, masking, G2 and Fresnel basis, not on α), so that the first points of
    # the first model do not carry start-up costs.
    warm = make_spec(ndf="ggx", alpha=0.3)
    to.tradeoff(warm.brdf(), tuple(sorted(warm.values.items())), mu=[0.5], max_budget=16)
    for values in MODELS:
        spec = make_spec(**values)
        t0 = time.perf_counter()
        data = to.tradeoff(spec.brdf(), tuple(sorted(spec.values.items())),
                           max_budget=args.max_budget, seed=args.seed)
        common.log(f"{values}: {time.perf_counter() - t0:.2f} s")
        print()
        print(markdown(data, f"GGX α = {values['alpha']}, Schlick F₀ = 0.04, height-correlated G2"))


if __name__ == "__main__":
    main()
