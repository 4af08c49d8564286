"""LUT build times and error tables: each kind at 32², 64², 128² with each quantisation.

For one model (default GGX, height-correlated Smith), builds the converged integrals of
each size once (E with F = 1 and with the Schlick basis on the refined grid of centres and
half-texel midpoints, and E_avg) and prints, per kind and quantisation, the maximum error
against the converged integral: of the table, after quantisation (texel centres), and
after quantisation and bilinear lookup (centres and half-texel offsets). Build times are
wall-clock seconds of one process on an idle machine, the first build after the compiled
kernel is warm.

    python bench/lut.py [ndf] [sizes...]       e.g.  python bench/lut.py ggx 32 64 128
"""
from __future__ import annotations

import sys
import time

sys.path.insert(0, ".")
from app.integrate.albedo import albedo  # noqa: E402
from app.lut.build import LobeKey, albedo_grid, average_grid  # noqa: E402
from app.lut.table import KINDS, QUANTISATIONS, make  # noqa: E402
from app.model import make_spec  # noqa: E402


def main() -> None:
    ndf = sys.argv[1] if len(sys.argv) > 1 else "ggx"
    sizes = [int(x) for x in sys.argv[2:]] or [32, 64, 128]
    key = LobeKey.of(make_spec(ndf=ndf).brdf())
    albedo(key.lobe(0.3, None), [0.5])      # compile the kernel outside the timings
    print(f"LUTs of ndf={ndf}, masking=smith, g2=height_correlated; axes roughness (α = r²) × μ, texel centres")
    print("\nbuild (converged integrals on the (2n−1)² refined grid, LUT_TOL 1e-6):")
    print(f"{'size':>6} {'E, F=1 [s]':>11} {'E, Schlick [s]':>15} {'E_avg [s]':>10} {'evaluations':>12}")
    for n in sizes:
        t = time.perf_counter()
        one = albedo_grid(key, n, "mu", "roughness", None)
        t1 = time.perf_counter() - t
        t = time.perf_counter()
        s = albedo_grid(key, n, "mu", "roughness", 5.0)
        t2 = time.perf_counter() - t
        t = time.perf_counter()
        avg = average_grid(key, n, "roughness")
        t3 = time.perf_counter() - t
        print(f"{n:>4}² {t1:>11.1f} {t2:>15.1f} {t3:>10.1f} {one.evaluations + s.evaluations + avg.evaluations:>12}")
    print("\nmax error (all channels) against the converged integral: table / quantised / bilinear lookup")
    for kind in KINDS:
        print(f"\n{kind} ({', '.join(KINDS[kind][0])})")
        print(f"{'size':>6} " + " ".join(f"{q:>30}" for q in QUANTISATIONS))
        for n in sizes:
            lut = make(kind, key, n, "mu", "roughness")
            cells = []
            for q in QUANTISATIONS:
                e = lut.errors(q)
                cells.append(f"{e['table']['max'].max():.1e} / {e['quantised']['max'].max():.1e} / "
                             f"{e['lookup']['max'].max():.1e}")
            print(f"{n:>4}² " + " ".join(f"{c:>30}" for c in cells))


if __name__ == "__main__":
    main()
