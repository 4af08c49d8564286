"""Is the albedo's E_error an honest bound? A sweep against brute force (minutes).

At the hard points — α ∈ {1e-3, 0.01, 0.05, 0.3, 1} and (α_x, α_y) = (0.05, 0.5) at
φ = 0.7, μ ∈ {0, 0.01, 0.05, 0.3, 1}, GGX and Beckmann, separable and height-
correlated G2, F = 1 — E from app.integrate.albedo at the default tol (and at 1e-6)
is compared with tests/reference.albedo_brute_force (adaptive cubature of f·μ_l over
(μ_l, φ_l), no slope space): the bound holds where |E − E_ref| ≤ E_error + ref_error.

    python bench/albedo_honesty.py [--tol 1e-5] [--ref-tol 1e-8] [--json out.json]
"""
from __future__ import annotations

import argparse
import json
import time

import common  # first: puts the checkout on sys.path

from app.integrate.albedo import albedo
from app.model import make_spec
from tests.reference import albedo_brute_force

ALPHAS = [(1e-3, None, 0.0), (0.01, None, 0.0), (0.05, None, 0.0), (0.3, None, 0.0),
          (1.0, None, 0.0), (0.05, 0.5, 0.7)]
MUS = [0.0, 0.01, 0.05, 0.3, 1.0]


def sweep(tols=(1e-5, 1e-6), ref_tol=1e-8) -> list[dict]:
    rows = []
    for ndf in ("ggx", "beckmann"):
        for g2 in ("separable", "height_correlated"):
            for ax, ay, phi in ALPHAS:
                brdf = make_spec(ndf=ndf, alpha=ax, alpha_y=ay, g2=g2, fresnel="none").brdf()
                for mu in MUS:
                    t0 = time.perf_counter()
                    ref, ref_err, _ = albedo_brute_force(brdf, mu, phi, tol=ref_tol)
                    row = {"ndf": ndf, "g2": g2, "alpha_x": ax, "alpha_y": ay or ax, "phi": phi,
                           "mu": mu, "ref": ref, "ref_error": ref_err,
                           "ref_seconds": time.perf_counter() - t0}
                    for tol in tols:
                        res = albedo(brdf, [mu], phi, tol)
                        diff = abs(float(res.E[0]) - ref)
                        row[f"tol{tol:g}"] = {"E": float(res.E[0]), "E_error": float(res.E_error[0]),
                                              "order": int(res.order[0]), "true_error": diff,
                                              "honest": diff <= float(res.E_error[0]) + ref_err + 1e-12}
                    rows.append(row)
                    flags = " ".join(f"{t:g}:{'ok' if row[f'tol{t:g}']['honest'] else 'VIOLATED'}"
                                     f"({row[f'tol{t:g}']['true_error']:.1e}/{row[f'tol{t:g}']['E_error']:.1e})"
                                     for t in tols)
                    common.log(f"{ndf:8s} {g2[:3]} α=({ax:g},{ay or ax:g}) φ={phi} μ={mu:<5g} "
                               f"ref {ref:.10f} ±{ref_err:.0e}  {flags}")
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tol", type=float, action="append")
    ap.add_argument("--ref-tol", type=float, default=1e-8)
    ap.add_argument("--json")
    a = ap.parse_args()
    rows = sweep(tuple(a.tol or (1e-5, 1e-6)), a.ref_tol)
    keys = [k for k in rows[0] if k.startswith("tol")]
    summary = {k: {"points": len(rows), "violations": sum(not r[k]["honest"] for r in rows),
                   "max_true_error": max(r[k]["true_error"] for r in rows),
                   "max_true_over_reported": max(r[k]["true_error"] / max(r[k]["E_error"] + r["ref_error"], 1e-300)
                                                 for r in rows)}
               for k in keys}
    print(json.dumps(summary, indent=1))
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"summary": summary, "rows": rows}, f, indent=1)


if __name__ == "__main__":
    main()
