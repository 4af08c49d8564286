"""Largest error of two approximations against the exact forms they stand for.

1. Hammon's G2 (Hammon 2017) against the exact height-correlated GGX G2 (Heitz 2014),
   over α ∈ [0.01, 1] and θ_l, θ_v ∈ [0, 89°].
   Compared in G2, not in V = G2/(4 μl μv): G2 is a fraction in [0, 1] (the share of
   microfacets both lit and seen), so its absolute error says how much light is gained
   or lost, at every angle on the same scale; V grows without bound towards grazing and
   its absolute error would be dominated by the last degree. The relative error is the
   same for both (they differ by the exact factor 4 μl μv) and is reported too.
2. Schlick's Fresnel, p = 5, F90 = 1, against the exact unpolarised dielectric
   Fresnel with the same F0 = ((η−1)/(η+1))², for η ∈ [1.33, 2.4] (water to
   diamond) and θ ∈ [0, 89°]. Compared in F (a reflectance in [0, 1]).

Each maximum is taken over a dense grid and then polished by a bounded local optimiser
started at the grid's worst point (the polished value is the one reported; the grid
value shows how flat the maximum is).

Run from the repository root:  python -m bench.approx_errors_g2_fresnel
"""
from __future__ import annotations

import time

import numpy as np
from scipy import optimize

from app.physics.fresnel import FRESNELS, dielectric_reflectance, f0_from_ior
from app.physics.g2 import G2_FORMS
from app.physics.ndf import make_ndf
from app.physics.vectors import direction_deg

THETA_MAX_DEG = 89.0


# --------------------------------------------------------------------------- Hammon

def g2_pair(alpha, theta_l_deg, theta_v_deg):
    """(hammon G2, exact height-correlated GGX G2) at broadcast angles; l, v in one plane
    (isotropic GGX: only μ matters for both forms)."""
    ndf = make_ndf("ggx", float(alpha))
    l = direction_deg(theta_l_deg, 0.0)
    v = direction_deg(theta_v_deg, 180.0)
    l, v = np.broadcast_arrays(l, v)
    mu_l, mu_v = l[..., 2], v[..., 2]
    ml_l, ml_v = ndf.mu_Lambda(l), ndf.mu_Lambda(v)
    kw = {"phi": None, "ndf": ndf, "lambda_phi": None}
    hm = G2_FORMS["hammon"].G2_and_V(mu_l, mu_v, ml_l, ml_v, **kw)[0]
    hc = G2_FORMS["height_correlated"].G2_and_V(mu_l, mu_v, ml_l, ml_v, **kw)[0]
    return hm, hc


def hammon_errors(n_alpha=200, step_deg=0.25):
    theta = np.arange(0.0, THETA_MAX_DEG + 1e-9, step_deg)
    alphas = np.geomspace(0.01, 1.0, n_alpha)
    worst_abs = (0.0, None)
    worst_rel = (0.0, None)
    per_alpha = []
    for a in alphas:
        hm, hc = g2_pair(a, theta[:, None], theta[None, :])
        err = hm - hc
        i = np.unravel_index(np.argmax(np.abs(err)), err.shape)
        rel = np.abs(err) / hc
        j = np.unravel_index(np.argmax(rel), rel.shape)
        per_alpha.append((a, abs(err[i]), theta[i[0]], theta[i[1]]))
        if abs(err[i]) > worst_abs[0]:
            worst_abs = (abs(err[i]), (a, theta[i[0]], theta[i[1]]))
        if rel[j] > worst_rel[0]:
            worst_rel = (rel[j], (a, theta[j[0]], theta[j[1]]))

    def neg_abs(x):
        hm, hc = g2_pair(x[0], x[1], x[2])
        return -abs(float(hm - hc))

    bounds = [(0.01, 1.0), (0.0, THETA_MAX_DEG), (0.0, THETA_MAX_DEG)]
    polished = optimize.minimize(neg_abs, np.array(worst_abs[1]), bounds=bounds, method="L-BFGS-B")
    return worst_abs, worst_rel, -polished.fun, polished.x, per_alpha


# --------------------------------------------------------------------------- Schlick

def schlick_error(eta, theta_deg):
    c = direction_deg(theta_deg, 0.0)[..., 2]
    f0 = float(f0_from_ior(eta))
    return FRESNELS["schlick"](f0=f0, f90=1.0, fresnel_p=5.0).F(c) - dielectric_reflectance(c, eta)


def schlick_errors(n_eta=200, step_deg=0.01):
    theta = np.arange(0.0, THETA_MAX_DEG + 1e-9, step_deg)
    worst = (0.0, None)
    worst_rel = (0.0, None)
    rows = []
    for eta in np.linspace(1.33, 2.4, n_eta):
        err = schlick_error(eta, theta)
        i = int(np.argmax(np.abs(err)))
        exact = dielectric_reflectance(direction_deg(theta, 0.0)[..., 2], eta)
        rel = np.abs(err) / exact
        j = int(np.argmax(rel))
        rows.append((eta, err[i], theta[i]))
        if abs(err[i]) > worst[0]:
            worst = (abs(err[i]), (eta, theta[i]))
        if rel[j] > worst_rel[0]:
            worst_rel = (rel[j], (eta, theta[j]))

    def neg_abs(x):
        return -abs(float(schlick_error(x[0], x[1])))

    polished = optimize.minimize(neg_abs, np.array(worst[1]), method="L-BFGS-B",
                                 bounds=[(1.33, 2.4), (0.0, THETA_MAX_DEG)])
    return worst, worst_rel, -polished.fun, polished.x, rows


def main():
    t0 = time.perf_counter()
    (g_abs, g_at), (g_rel, g_rel_at), g_pol, g_pol_at, per_alpha = hammon_errors()
    t1 = time.perf_counter()
    (s_abs, s_at), (s_rel, s_rel_at), s_pol, s_pol_at, rows = schlick_errors()
    t2 = time.perf_counter()

    print("Approximation errors against the exact forms (θ ∈ [0, 89°])\n")
    print("| approximation | exact form | range | max |error| | where | max rel. error | where |")
    print("|---|---|---|---|---|---|---|")
    print(f"| hammon G2 (Hammon 2017) | height-correlated GGX G2 (Heitz 2014) | α ∈ [0.01, 1] | "
          f"{g_pol:.4f} (grid {g_abs:.4f}) | α={g_pol_at[0]:.4g}, θ_l={g_pol_at[1]:.2f}°, "
          f"θ_v={g_pol_at[2]:.2f}° | {g_rel:.3f} | α={g_rel_at[0]:.3g}, θ_l={g_rel_at[1]:g}°, "
          f"θ_v={g_rel_at[2]:g}° |")
    print(f"| Schlick F, p=5, F90=1 | exact dielectric, same F0 | η ∈ [1.33, 2.4] | "
          f"{s_pol:.4f} (grid {s_abs:.4f}) | η={s_pol_at[0]:.4g}, θ={s_pol_at[1]:.2f}° | "
          f"{s_rel:.3f} | η={s_rel_at[0]:.3g}, θ={s_rel_at[1]:g}° |")

    print("\nHammon: largest |ΔG2| per α (grid 0.25°)")
    print("| α | max |ΔG2| | θ_l | θ_v |")
    print("|---|---|---|---|")
    for a, e, tl, tv in per_alpha[:: len(per_alpha) // 8] + [per_alpha[-1]]:
        print(f"| {a:.3g} | {e:.4f} | {tl:g}° | {tv:g}° |")

    print("\nSchlick: F − F_exact at its largest |·| per η (grid 0.01°)")
    print("| η | F0 | F − F_exact | θ |")
    print("|---|---|---|---|")
    for eta, e, th in rows[:: len(rows) // 6] + [rows[-1]]:
        print(f"| {eta:.3g} | {float(f0_from_ior(eta)):.4f} | {e:+.4f} | {th:g}° |")
    print(f"\n(hammon: {t1 - t0:.1f} s, schlick: {t2 - t1:.1f} s)")


if __name__ == "__main__":
    main()
