"""Time to accuracy of the directional albedo E(μ), and Monte Carlo at equal time.

* The E(μ, α) table of Kulla-Conty compensation: 32 μ × 32 α (μ = 0..1, α = r², r =
  0.01..1, both ends included), GGX, height-correlated G2, F = 1, asked for max error
  ≤ 1e-5. Timed; then checked against a reference table at tol 1e-9: the true max
  error and the max reported E_error.
* A single E(μ) at ≤ 1e-6: GGX, h-c G2, Schlick (the page's model), at μ ∈ {0, 0.01,
  0.1, 0.5, 1} × α ∈ {0.01, 0.3, 1}; the median and the largest time over those 15.
* Monte Carlo at equal time: E(μ = 0.5, α = 0.3) by D·cos-sampled microfacet normals
  (l the mirror of v about m; estimator F·G2·(v·m)/(μ_v μ_m)) and by cosine-weighted l
  (estimator π f), with as many samples as fit in the quadrature's time, vectorised
  through BRDF.evaluate (fast path). Their RMS error over repeats against the
  quadrature at tol 1e-10.
"""
from __future__ import annotations

import time

import common  # first: puts the checkout on sys.path

import numpy as np

from app.integrate.albedo import albedo
from app.model import make_spec

TABLE_MU = np.linspace(0.0, 1.0, 32)
TABLE_ALPHA = np.linspace(0.01, 1.0, 32) ** 2


def table(tol: float, alphas=TABLE_ALPHA):
    """E[α, μ] and E_error[α, μ] for the 32 × 32 table (one albedo call per α)."""
    E = np.empty((len(alphas), TABLE_MU.size))
    err = np.empty_like(E)
    evals = 0
    for i, a in enumerate(alphas):
        res = albedo(make_spec(alpha=float(a), fresnel="none").brdf(), TABLE_MU, 0.0, tol)
        E[i], err[i] = res.E, res.E_error
        evals += res.evaluations
    return E, err, evals


def mc_dcos(brdf, mu_v: float, n: int, rng) -> float:
    """E by D·cos sampling of m in α-stretched slope space (u uniform → r̃² = C⁻¹(u))."""
    ndf = brdf.ndf
    v = np.array([np.sqrt(1.0 - mu_v * mu_v), 0.0, mu_v])
    u = rng.random(n)
    psi = 2.0 * np.pi * rng.random(n)
    rho = np.sqrt(ndf.radial_cdf_inv(u))
    m = np.stack([-ndf.alpha_x * rho * np.cos(psi), -ndf.alpha_y * rho * np.sin(psi), np.ones(n)], -1)
    m /= np.linalg.norm(m, axis=-1, keepdims=True)
    vm = m @ v
    l = 2.0 * vm[:, None] * m - v
    ok = (vm > 0) & (l[:, 2] > 0)
    # E = ∫ f μ_l dl = E_m[f μ_l 4 (v·m) / (D μ_m)] with m ~ D μ_m, l = reflect(v, m)
    # (dl = 4 (v·m) dm); f = D F G2 / (4 μ_l μ_v): the estimator is F G2 (v·m)/(μ_v μ_m).
    q = brdf.evaluate(l[ok], np.broadcast_to(v, l[ok].shape), ("F", "G2"))
    return float(np.sum(q["F"] * q["G2"] * vm[ok] / (mu_v * m[ok, 2])) / n)


def mc_cosine(brdf, mu_v: float, n: int, rng) -> float:
    """E by cosine-weighted l: pdf μ_l/π, estimator π f(l, v)."""
    v = np.array([np.sqrt(1.0 - mu_v * mu_v), 0.0, mu_v])
    r = np.sqrt(rng.random(n))
    phi = 2.0 * np.pi * rng.random(n)
    l = np.stack([r * np.cos(phi), r * np.sin(phi), np.sqrt(np.maximum(0.0, 1.0 - r * r))], -1)
    return float(np.pi * np.mean(brdf.f(l, np.broadcast_to(v, l.shape))))


def samples_in(fn, brdf, mu_v, seconds: float, rng) -> int:
    """How many samples of ``fn`` fit in ``seconds`` (measured at 2^16, then scaled)."""
    n0 = 1 << 16
    fn(brdf, mu_v, n0, rng)
    t0 = time.perf_counter()
    fn(brdf, mu_v, n0, rng)
    rate = n0 / (time.perf_counter() - t0)
    return max(64, int(rate * seconds))


def run(quick: bool = False) -> dict:
    out: dict = {}
    repeat = 3 if quick else 7

    # --- the 32 × 32 table at 1e-5
    table(1e-5)                                   # warm (compilation, caches)
    times, cpu = [], []
    out["accuracy_loadavg"] = common.loadavg()
    for _ in range(repeat):
        c0 = time.process_time()
        t0 = time.perf_counter()
        E, err, evals = table(1e-5)
        times.append(time.perf_counter() - t0)
        cpu.append(time.process_time() - c0)
    out["albedo_table_seconds"] = common.median(times)
    out["albedo_table_cpu_seconds"] = common.median(cpu)
    out["albedo_table_evaluations"] = evals
    out["albedo_table_max_reported_error"] = float(err.max())
    ref_alphas = TABLE_ALPHA[::4] if quick else TABLE_ALPHA
    rows = slice(None, None, 4) if quick else slice(None)
    common.log(f"  table: {out['albedo_table_seconds'] * 1e3:.0f} ms; reference at 1e-9 "
               f"({len(ref_alphas)} of 32 α) ...")
    E_ref, err_ref, _ = table(1e-9, ref_alphas)
    true = np.abs(E[rows] - E_ref)
    out["albedo_table_max_true_error"] = float(true.max())
    out["albedo_table_reference_error"] = float(err_ref.max())
    out["albedo_table_bound_violations"] = int(np.sum(true > err[rows] + err_ref))

    # --- a single E(μ) at 1e-6
    cases = [(mu, a) for mu in (0.0, 0.01, 0.1, 0.5, 1.0) for a in (0.01, 0.3, 1.0)]
    per_case = []
    for mu, a in cases:
        brdf = make_spec(alpha=a).brdf()
        albedo(brdf, [mu], 0.0, 1e-6)
        ts = []
        for _ in range(repeat):
            t0 = time.perf_counter()
            res = albedo(brdf, [mu], 0.0, 1e-6)
            ts.append(time.perf_counter() - t0)
        per_case.append((common.median(ts), mu, a, float(res.E_error[0]), int(res.order[0])))
    out["albedo_single_seconds"] = common.median([c[0] for c in per_case])
    worst = max(per_case)
    out["albedo_single_max_seconds"] = worst[0]
    out["albedo_single_worst_case"] = {"mu": worst[1], "alpha": worst[2], "order": worst[4]}
    out["albedo_single_max_reported_error"] = max(c[3] for c in per_case)

    # --- Monte Carlo at the time of the quadrature (μ = 0.5, α = 0.3, the page's model)
    brdf = make_spec(alpha=0.3).brdf()
    mu_v = 0.5
    ref = float(albedo(brdf, [mu_v], 0.0, 1e-10).E[0])
    res = albedo(brdf, [mu_v], 0.0, 1e-6)
    ts = []
    for _ in range(repeat):
        t0 = time.perf_counter()
        albedo(brdf, [mu_v], 0.0, 1e-6)
        ts.append(time.perf_counter() - t0)
    t_quad = common.median(ts)
    out["mc_budget_seconds"] = t_quad
    out["mc_quadrature_error"] = abs(float(res.E[0]) - ref)
    rng = np.random.default_rng(7)
    for name, fn in (("dcos", mc_dcos), ("cosine", mc_cosine)):
        n = samples_in(fn, brdf, mu_v, t_quad, rng)
        errs = [fn(brdf, mu_v, n, rng) - ref for _ in range(20 if quick else 50)]
        out[f"mc_{name}_samples"] = n
        out[f"mc_{name}_rms_error"] = float(np.sqrt(np.mean(np.square(errs))))
    return out


def report(r: dict) -> list[str]:
    w = r["albedo_single_worst_case"]
    return [
        "time to accuracy, E(μ) by quadrature",
        f"  32×32 E(μ, α) table at ≤ 1e-5 : {r['albedo_table_seconds'] * 1e3:8.1f} ms "
        f"({r['albedo_table_cpu_seconds'] * 1e3:.0f} ms CPU, load {r['accuracy_loadavg']}; "
        f"{r['albedo_table_evaluations']:,} evaluations); max reported error "
        f"{r['albedo_table_max_reported_error']:.1e}, true {r['albedo_table_max_true_error']:.1e}, "
        f"bound violated at {r['albedo_table_bound_violations']} entries",
        f"  single E(μ) at ≤ 1e-6        : median {r['albedo_single_seconds'] * 1e3:6.2f} ms, "
        f"max {r['albedo_single_max_seconds'] * 1e3:6.2f} ms (μ={w['mu']}, α={w['alpha']}, order {w['order']})",
        f"  Monte Carlo in the same {r['mc_budget_seconds'] * 1e3:.2f} ms (μ=0.5, α=0.3): "
        f"quadrature error {r['mc_quadrature_error']:.1e}; D·cos sampling "
        f"{r['mc_dcos_samples']:,} samples, RMS error {r['mc_dcos_rms_error']:.1e}; cosine "
        f"{r['mc_cosine_samples']:,} samples, RMS error {r['mc_cosine_rms_error']:.1e}",
    ]


if __name__ == "__main__":
    print("\n".join(report(run(quick=True))))
