"""Is the albedo's E_error an honest bound? A sweep against brute force (minutes).

At the hard points — α ∈ {1e-3, 0.01, 0.05, 0.3, 1} and (α_x, α_y) = (0.05, 0.5) at
φ = 0.7, μ ∈ {0, 0.01, 0.05, 0.3, 1}, GGX and Beckmann, separable and height-
correlated G2, F = 1 — E from app.integrate.albedo at the default tol (and at 1e-6)
is compared with tests/reference.albedo_brute_force (adaptive cubature of f·μ_l over
(μ_l, φ_l), no slope space), or, where that misses the peak, with the physics tests'
graded rule about the mirror direction (choose_reference): the bound holds where
|E − E_ref| ≤ E_error + ref_error.

    python bench/albedo_honesty.py --rejudge out.json   # new verdicts from saved rows

    python bench/albedo_honesty.py [--tol 1e-5] [--ref-tol 1e-8] [--json out.json]
"""
from __future__ import annotations

import argparse
import json
import time

import common  # first: puts the checkout on sys.path

import numpy as np

from app.integrate.albedo import albedo
from app.model import make_spec
from tests.physics.conftest import l_sphere_rule
from tests.reference import albedo_brute_force

ALPHAS = [(1e-3, None, 0.0), (0.01, None, 0.0), (0.05, None, 0.0), (0.3, None, 0.0),
          (1.0, None, 0.0), (0.05, 0.5, 0.7)]
MUS = [0.0, 0.01, 0.05, 0.3, 1.0]


def graded_reference(brdf, mu: float, phi: float, scale: float):
    """E by the physics tests' graded rule over the sphere of l (tests/physics/conftest
    l_sphere_rule: spherical coordinates about v, nodes graded towards the mirror
    direction with width ~α), at 192 and 384 nodes per piece; its error is taken as
    twice their difference. Independent of the albedo's slope space and of the adaptive
    brute force, and it cannot miss a narrow peak: the peak is where its nodes are."""
    st = np.sqrt(max(0.0, 1.0 - mu * mu))
    v = np.array([st * np.cos(phi), st * np.sin(phi), mu])
    values = []
    for n in (192, 384):
        l, w = l_sphere_rule(v, scale, n_theta=n, n_psi=n)
        f = brdf.f(l, np.broadcast_to(v, l.shape))
        values.append(float(np.sum(np.where(l[:, 2] > 0, f * l[:, 2], 0.0) * w)))
    return values[1], 2.0 * abs(values[1] - values[0])


def choose_reference(bf, bf_err, gr, gr_err):
    """(reference, its error, whether the two agree). Where they agree within their
    error estimates: the one with the smaller estimate. The adaptive cubature can miss a narrow peak
    altogether (Beckmann at α ≤ 0.01: 0 ± 0): where they disagree and the graded rule is
    sure of itself (its error below a tenth of the disagreement), the graded rule;
    otherwise the brute force (the graded rule is then the uncertain one: GGX at
    α = 1e-3, where its error estimate is 2e-6)."""
    diff = abs(bf - gr)
    if bool(diff <= bf_err + gr_err + 1e-12):
        return (bf, bf_err, True) if bf_err <= gr_err else (gr, gr_err, True)
    if bool(gr_err < 0.1 * diff):
        return gr, gr_err, False
    return bf, bf_err, False


def sweep(tols=(1e-5, 1e-6), ref_tol=1e-8, ndfs=("ggx", "beckmann"), alphas=None) -> list[dict]:
    rows = []
    for ndf in ndfs:
        for g2 in ("separable", "height_correlated"):
            for ax, ay, phi in ALPHAS:
                if alphas is not None and (ax, ay) not in alphas:
                    continue
                brdf = make_spec(ndf=ndf, alpha=ax, alpha_y=ay, g2=g2, fresnel="none").brdf()
                for mu in MUS:
                    t0 = time.perf_counter()
                    bf, bf_err, _ = albedo_brute_force(brdf, mu, phi, tol=ref_tol)
                    gr, gr_err = graded_reference(brdf, mu, phi, min(ax, ay or ax))
                    ref, ref_err, agree = choose_reference(bf, bf_err, gr, gr_err)
                    row = {"ndf": ndf, "g2": g2, "alpha_x": ax, "alpha_y": ay or ax, "phi": phi,
                           "mu": mu, "ref": ref, "ref_error": ref_err,
                           "brute_force": bf, "brute_force_error": bf_err,
                           "graded": gr, "graded_error": gr_err, "references_agree": agree,
                           "ref_seconds": time.perf_counter() - t0}
                    for tol in tols:
                        res = albedo(brdf, [mu], phi, tol)
                        diff = abs(float(res.E[0]) - ref)
                        row[f"tol{tol:g}"] = {"E": float(res.E[0]), "E_error": float(res.E_error[0]),
                                              "order": int(res.order[0]), "true_error": diff,
                                              "honest": bool(diff <= float(res.E_error[0]) + ref_err + 1e-12)}
                    rows.append(row)
                    flags = " ".join(f"{t:g}:{'ok' if row[f'tol{t:g}']['honest'] else 'VIOLATED'}"
                                     f"({row[f'tol{t:g}']['true_error']:.1e}/{row[f'tol{t:g}']['E_error']:.1e})"
                                     for t in tols)
                    common.log(f"{ndf:8s} {g2[:3]} α=({ax:g},{ay or ax:g}) φ={phi} μ={mu:<5g} "
                               f"ref {ref:.10f} ±{ref_err:.0e} (brute force {bf:.10f} ±{bf_err:.0e}, "
                               f"graded {gr:.10f} ±{gr_err:.0e})  {flags}")
    return rows


def main() -> None:
    ap = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    ap.add_argument("--tol", type=float, action="append")
    ap.add_argument("--ref-tol", type=float, default=1e-8)
    ap.add_argument("--json")
    ap.add_argument("--rejudge", help="recompute the verdicts of a saved --json file")
    ap.add_argument("--ndfs", default="ggx,beckmann", help="a subset, comma-separated")
    ap.add_argument("--alphas", help="a subset of the isotropic α, comma-separated (e.g. 0.001,0.01)")
    a = ap.parse_args()
    if a.rejudge:
        with open(a.rejudge) as f:
            rows = json.load(f)["rows"]
        for r in rows:
            r["ref"], r["ref_error"], r["references_agree"] = choose_reference(
                r["brute_force"], r["brute_force_error"], r["graded"], r["graded_error"])
            for k in [k for k in r if k.startswith("tol")]:
                r[k]["true_error"] = abs(r[k]["E"] - r["ref"])
                r[k]["honest"] = bool(r[k]["true_error"] <= r[k]["E_error"] + r["ref_error"] + 1e-12)
    else:
        alphas = None if not a.alphas else {(float(x), None) for x in a.alphas.split(",")}
        rows = sweep(tuple(a.tol or (1e-5, 1e-6)), a.ref_tol, tuple(a.ndfs.split(",")), alphas)
    keys = [k for k in rows[0] if k.startswith("tol")]
    summary = {k: {"points": len(rows), "violations": sum(not r[k]["honest"] for r in rows),
                   "references_disagree": sum(not r["references_agree"] for r in rows),
                   "max_true_error": max(r[k]["true_error"] for r in rows),
                   "max_true_over_reported": max(r[k]["true_error"] / max(r[k]["E_error"] + r["ref_error"], 1e-300)
                                                 for r in rows)}
               for k in keys}
    print(json.dumps(summary, indent=1))
    if a.json:
        with open(a.json, "w") as f:
            json.dump({"summary": summary, "rows": rows}, f, indent=1, default=float)


if __name__ == "__main__":
    main()
