"""How much the pointwise error of the advice grows between its nodes: for several scenes,
every alternative's largest relative error of f on the advice's nodes against a grid 4×
finer in every angle and 21 α nodes. The largest ratio sets POINTWISE_SAFETY
(app/analysis/pointwise.py).

    python bench/advise_pointwise.py
"""
import numpy as np

from app.analysis import pointwise as pw
from app.analysis.advise import Scene, advise

SCENES = [({"alpha": 0.4, "fresnel": "dielectric"}, Scene(0.3, 0.5, 60.0)),
          ({"alpha": 0.4}, Scene(0.05, 1.0, 80.0)),
          ({"ndf": "beckmann", "alpha": 0.2}, Scene(0.02, 0.5, 85.0)),
          ({"alpha": 0.1, "fresnel": "conductor"}, Scene(0.01, 0.3, 70.0))]


def main() -> None:
    largest = 0.0
    for given, scene in SCENES:
        r = advise(given, 0.01, scene, metric="pointwise")
        alphas = np.geomspace(scene.alpha_min, scene.alpha_max, 21)
        ref = pw.f_grid(r["current"], scene, alphas, 4 * (pw.N_THETA - 1) + 1, 4 * (pw.N_PHI - 1) + 1)
        for e in r["alternatives"]:
            if e["max_difference"] is None:
                continue
            alt = pw.f_grid(e["model"], scene, alphas, 4 * (pw.N_THETA - 1) + 1, 4 * (pw.N_PHI - 1) + 1)
            fine = max(float(np.max(pw.relative_error(a, b))) for a, b in zip(ref.f, alt.f))
            ratio = fine / max(e["max_difference"], 1e-300)
            largest = max(largest, ratio)
            print(f"{given} {scene}: {e['label']:24s} nodes {e['max_difference']:.4g}  "
                  f"fine {fine:.4g}  ratio {ratio:.3f}")
    print(f"largest ratio {largest:.3f} (POINTWISE_SAFETY = {pw.POINTWISE_SAFETY})")


if __name__ == "__main__":
    main()
