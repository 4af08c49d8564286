"""The samples panel draws φ in degrees like every other angle of the page (it was in
radians), and its density stays per steradian: a uniform hemisphere reads 1/(2π)."""
import numpy as np

from app.figures.samples import FIGURE_BINS, samples_figure

SPEC = {"ndf": "ggx", "alpha": 0.3, "fresnel": "none", "masking": "smith",
        "g2": "height_correlated", "kd": 0.0}


def _uniform_hemisphere(n, seed=3):
    rng = np.random.default_rng(seed)
    z = rng.random(n)                       # uniform in cos θ and φ: uniform in solid angle
    phi = rng.uniform(-np.pi, np.pi, n)
    r = np.sqrt(1 - z ** 2)
    return {"x": r * np.cos(phi), "y": r * np.sin(phi), "z": z, "pdf": np.full(n, 1 / (2 * np.pi)),
            "sampler": "uniform", "seed": 3, "chi2": 1.0, "dof": 1, "p_value": 0.5,
            "below_horizon": 0, "below_horizon_expected": 0.0, "E": 1.0, "E_error": 0.0}


def test_phi_axes_in_degrees_and_density_per_steradian():
    n = 20000
    fig = samples_figure(_uniform_hemisphere(n), SPEC, 30.0)
    lay = fig["layout"]
    for key in ("xaxis", "xaxis2"):
        assert "degrees" in lay[key]["title"]["text"] and lay[key]["range"] == [-180, 180]
    sampled = fig["data"][0]
    x = np.asarray(sampled["x"])
    assert x.min() < -170 and x.max() > 170
    assert sampled["xbins"]["end"] - sampled["xbins"]["start"] == 360
    # sum of the weights in one bin / count = density; a uniform hemisphere is 1/(2π) per sr
    n_cos, n_phi = FIGURE_BINS
    counts, _, _ = np.histogram2d(x, sampled["y"], bins=[n_phi, n_cos], range=[[-180, 180], [0, 1]])
    density = counts * np.asarray(sampled["z"])[0]
    assert abs(density.mean() - 1 / (2 * np.pi)) < 1e-3
