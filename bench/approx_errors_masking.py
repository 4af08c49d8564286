"""Largest error of each masking approximation against exact Smith G1.

Over α ∈ [0.01, 1] (64 values, log-spaced) and θ ∈ [0, 89°] (0.25° steps), isotropic:
walter (Beckmann, Blinn-Phong), karis, schlick_direct, schlick_ibl (GGX), and
Blinn-Phong's own ``smith`` (Walter's Beckmann substitution), against the NDF's exact
Smith G1 (closed form, or the Smith integral for Blinn-Phong).

Run: python -m bench.approx_errors_masking
"""
from __future__ import annotations

import numpy as np

from app.physics.masking import G1, MASKINGS
from app.physics.ndf import make_ndf
from app.physics.vectors import direction_deg

ALPHAS = np.geomspace(0.01, 1.0, 64)
THETAS = np.arange(0.0, 89.0 + 1e-9, 0.25)
CASES = [("walter", "beckmann", "smith"), ("walter", "blinn_phong", "smith_numeric"),
         ("smith", "blinn_phong", "smith_numeric"), ("karis", "ggx", "smith"),
         ("schlick_direct", "ggx", "smith"), ("schlick_ibl", "ggx", "smith")]


def worst(masking: str, ndf_name: str, exact: str) -> tuple[float, float, float, float]:
    """(max |ΔG1|, α, θ there, max |ΔG1|/G1_exact)."""
    w = direction_deg(THETAS, 0.0)
    best = (0.0, 0.0, 0.0, 0.0)
    for alpha in ALPHAS:
        ndf = make_ndf(ndf_name, float(alpha))
        g = G1(w[:, 2], MASKINGS[masking].mu_Lambda(ndf, w))
        g_exact = G1(w[:, 2], MASKINGS[exact].mu_Lambda(ndf, w))
        err = np.abs(g - g_exact)
        k = int(np.argmax(err))
        rel = float(np.max(err / g_exact))
        if err[k] > best[0]:
            best = (float(err[k]), float(alpha), float(THETAS[k]), max(rel, best[3]))
        else:
            best = (*best[:3], max(rel, best[3]))
    return best


def main() -> None:
    print(f"{'approximation':16s} {'NDF':12s} {'against':14s} {'max |ΔG1|':>10s} {'at α':>7s} "
          f"{'at θ':>6s} {'max rel':>8s}")
    for masking, ndf_name, exact in CASES:
        err, alpha, theta, rel = worst(masking, ndf_name, exact)
        print(f"{masking:16s} {ndf_name:12s} {exact:14s} {err:10.4f} {alpha:7.3f} {theta:6.2f} {rel:8.3f}")


if __name__ == "__main__":
    main()
