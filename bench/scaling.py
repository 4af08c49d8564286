"""How cost grows: the 3-D lobe against its grid, the albedo against its accuracy.

* lobe3d: n_theta × n_phi from the page's 46 × 91 up to the limit (BRDF_MAX_GRID_POINTS,
  250 000 points), in-process, split into compute (app.quantities.lobe_grid: directions
  and f), figure (app.figures.lobe3d_figure) and encoding (app.figures.to_json) — the
  work of GET /api/v1/figures/lobe3d without HTTP. Nanoseconds per point show whether
  cost is linear in the number of points.
* albedo: E(μ) at the page's 17 μ plus E_avg (app.quantities.albedo_curve, what GET
  /api/v1/albedo computes), GGX α = 0.3, height-correlated, Schlick, for tol from 1e-3
  to 1e-8: time, integrand evaluations, the largest reported E_error, and the true
  error against tol 1e-10 (every μ refined to the largest order).
"""
from __future__ import annotations

import time

import common  # first: puts the checkout on sys.path

import numpy as np

from app import figures, quantities
from app.config import Settings
from app.model import make_spec

GRIDS = [(46, 91), (91, 181), (181, 361), (250, 721), (353, 708)]
TOLS = [1e-3, 1e-4, 1e-5, 1e-6, 1e-7, 1e-8]


def lobe3d_rows(repeat: int, grids=GRIDS) -> list[dict]:
    brdf = make_spec().brdf()
    spec = make_spec().values
    limit = Settings.from_env().max_grid_points
    rows = []
    for n_theta, n_phi in grids:
        if n_theta * n_phi > limit:
            continue
        parts = {"compute": [], "figure": [], "json": []}
        for r in range(repeat + 1):
            t0 = time.perf_counter()
            data = quantities.lobe_grid(brdf, 45.0, 0.0, n_theta, n_phi)
            t1 = time.perf_counter()
            fig = figures.lobe3d_figure(data, spec, 45.0, 0.0)
            t2 = time.perf_counter()
            body = figures.to_json(fig)
            t3 = time.perf_counter()
            if r:                                   # the first round is a warm-up
                parts["compute"].append(t1 - t0)
                parts["figure"].append(t2 - t1)
                parts["json"].append(t3 - t2)
        points = n_theta * n_phi
        row = {"n_theta": n_theta, "n_phi": n_phi, "points": points, "bytes": len(body)}
        for k, ts in parts.items():
            row[f"{k}_ms"] = 1e3 * common.median(ts)
        row["total_ms"] = row["compute_ms"] + row["figure_ms"] + row["json_ms"]
        row["ns_per_point"] = 1e6 * row["total_ms"] / points
        rows.append(row)
    return rows


def albedo_rows(repeat: int, tols=TOLS) -> list[dict]:
    brdf = make_spec(alpha=0.3).brdf()
    mu = np.linspace(0.0, 1.0, 17)
    ref = quantities.albedo_curve(brdf, mu, 0.0, 1e-10)   # every μ to ORDER_MAX
    rows = []
    for tol in tols:
        quantities.albedo_curve(brdf, mu, 0.0, tol)
        ts = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            res = quantities.albedo_curve(brdf, mu, 0.0, tol)
            ts.append(time.perf_counter() - t0)
        rows.append({
            "tol": tol, "ms": 1e3 * common.median(ts), "evaluations": int(res["evaluations"]),
            "max_E_error": float(np.max(res["E_error"])),
            "true_max_E_error": float(np.max(np.abs(res["E"] - ref["E"]))),
            "E_avg_error": float(res["E_avg_error"]),
            "true_E_avg_error": abs(float(res["E_avg"]) - float(ref["E_avg"]))})
    return rows


def run(quick: bool = False) -> dict:
    repeat = 2 if quick else 7
    # quick: the page's grid, two larger ones and the limit; tolerances a decade apart
    rows = lobe3d_rows(repeat, [GRIDS[0], GRIDS[1], GRIDS[2], GRIDS[-1]] if quick else GRIDS)
    ns = [r["ns_per_point"] for r in rows]
    out = {"lobe3d_scaling": rows,
           # largest/smallest cost per point over the grids: 1 would be exactly linear
           "lobe3d_ns_per_point_spread": max(ns) / min(ns)}
    common.log("  lobe3d grids done; albedo against tol ...")
    out["albedo_scaling"] = albedo_rows(repeat, TOLS[::2] if quick else TOLS)
    return out


def report(r: dict) -> list[str]:
    lines = ["lobe3d figure, in-process (compute + figure + JSON), cost against grid size",
             "  grid        points   compute  figure    json   total ms   ns/point   bytes"]
    for x in r["lobe3d_scaling"]:
        lines.append(f"  {x['n_theta']:3d}×{x['n_phi']:<4d} {x['points']:8,d} {x['compute_ms']:8.1f} "
                     f"{x['figure_ms']:7.1f} {x['json_ms']:7.1f} {x['total_ms']:9.1f} "
                     f"{x['ns_per_point']:9.0f} {x['bytes']:9,d}")
    lines += ["albedo at n = 17 plus E_avg (GGX α=0.3, h-c, Schlick), cost against tolerance",
              "  tol      ms      evaluations   max E_error  true max error  E_avg err (true)"]
    for x in r["albedo_scaling"]:
        lines.append(f"  {x['tol']:.0e} {x['ms']:7.2f} {x['evaluations']:14,d}     {x['max_E_error']:.1e}"
                     f"        {x['true_max_E_error']:.1e}      {x['E_avg_error']:.1e} ({x['true_E_avg_error']:.1e})")
    return lines


if __name__ == "__main__":
    print("\n".join(report(run(quick=True))))
