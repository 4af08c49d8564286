"""Time for the environment sphere's refinement at rest (static/js/panels/refine.js) to reach its
target noise: renders of seeds 1, 2, … at ``samples`` per pixel through the view's
pipeline (what the data route computes for each), averaged as the page averages them
(render.averaged), one after the other as the page asks for them, until the stated
noise is ≤ 5 %. Each render's wall-clock seconds, the running total and the noise.
The page adds its first figure, the transfer of each render's JSON and one heavy
worker's queue; this is the renders' share.

    python bench/sphere_refine.py [samples] [n] [environment]    e.g. python bench/sphere_refine.py 128 256 studio
"""
from __future__ import annotations

import sys
import time

import numpy as np

from common import log

#: the page's target (refine.js TARGET_NOISE)
TARGET_NOISE = 0.05
#: renders at most: a bound, should a case never get there
MAX_RENDERS = 200


def main() -> None:
    from app.config import Settings
    from app.environment.render import averaged, stated_noise
    from app.views import VIEWS, run
    samples = int(sys.argv[1]) if len(sys.argv) > 1 else 128
    n = int(sys.argv[2]) if len(sys.argv) > 2 else 256
    environment = sys.argv[3] if len(sys.argv) > 3 else "studio"
    view = VIEWS["sphere_env"]
    pairs, t0 = [], time.perf_counter()
    for seed in range(1, MAX_RENDERS + 1):
        t = time.perf_counter()
        data = run(view, view.query(samples=samples, seed=seed, n=n, environment=environment), Settings()).data
        on = ~np.isnan(data["std_error"])
        pairs.append((data["radiance"][on], data["std_error"][on]))
        noise = stated_noise(*averaged(pairs))["relative"]
        log(f"render {seed:3d}: {samples * seed:5d} samples/pixel, {time.perf_counter() - t:5.2f} s, "
            f"total {time.perf_counter() - t0:6.1f} s, noise {100 * noise:.2f} %")
        if noise <= TARGET_NOISE:
            break
    print(f"n={n} {environment} at {samples} samples a render: {len(pairs)} renders, "
          f"{samples * len(pairs)} samples/pixel, {time.perf_counter() - t0:.1f} s to {100 * noise:.2f} %")


if __name__ == "__main__":
    main()
