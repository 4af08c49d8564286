"""The known analytic model the data-set and fit tests write and read back: GGX with
α = 0.2 and Schlick F0 = 0.9 in red (0.6 in green, 0.3 in blue), height-correlated
Smith G2, plus a Lambertian kd = 0.1 — in closed form here, apart from the app."""
import functools
import math

import numpy as np

ALPHA, KD = 0.2, 0.1
F0 = {"r": 0.9, "g": 0.6, "b": 0.3}


def ggx_f(l, v, alpha=ALPHA, f0=F0["r"], kd=KD):
    """f = D F G2 / (4 μ_l μ_v) + kd/π (Walter et al. 2007: D eq. 33, Λ eq. 72 of Heitz
    2014, G2 height-correlated Heitz 2014 eq. 99; Schlick 1994)."""
    l, v = np.asarray(l, float), np.asarray(v, float)
    h = l + v
    h = h / np.linalg.norm(h, axis=-1, keepdims=True)
    cos_h = h[..., 2]
    tan2_h = (1.0 - cos_h ** 2) / cos_h ** 2
    D = alpha ** 2 / (math.pi * cos_h ** 4 * (alpha ** 2 + tan2_h) ** 2)

    def Lambda(w):
        mu = w[..., 2]
        tan2 = (1.0 - mu ** 2) / mu ** 2
        return (-1.0 + np.sqrt(1.0 + alpha ** 2 * tan2)) / 2.0
    G2 = 1.0 / (1.0 + Lambda(l) + Lambda(v))
    F = f0 + (1.0 - f0) * (1.0 - np.sum(v * h, axis=-1)) ** 5
    return D * F * G2 / (4.0 * l[..., 2] * v[..., 2]) + kd / math.pi


def model(channel="r"):
    """The same model as the app spells it."""
    return {"ndf": "ggx", "masking": "smith", "g2": "height_correlated", "fresnel": "schlick",
            "alpha": ALPHA, "f0": F0[channel], "kd": KD}


@functools.cache
def merl_bytes() -> bytes:
    from app.datasets import merl, tabulate
    from app.model import make_spec
    table = tabulate.merl_table([make_spec(**model(c)).brdf() for c in "rgb"])
    return merl.write(table)


#: a measured-looking material: two GGX lobes (α = 0.06 and 0.3, the second weighted
#: 0.35), a coppery Schlick F0 per channel, a little diffuse, 3 % multiplicative noise
#: (fixed seed) and cells near grazing (θ_d > 80°) left unmeasured, as measurements are
MEASURED_STYLE = {"ndf": "ggx", "alpha": 0.06, "alpha2": 0.3, "lobe_mix": 0.35, "kd": 0.02}
MEASURED_F0 = {"r": 0.95, "g": 0.64, "b": 0.54}


@functools.cache
def measured_style_bytes() -> bytes:
    from app.datasets import merl, tabulate
    from app.model import make_spec
    table = tabulate.merl_table([make_spec(**MEASURED_STYLE, f0=MEASURED_F0[c]).brdf() for c in "rgb"])
    rng = np.random.default_rng(2003)
    noisy = np.where(table >= 0, table * np.exp(0.03 * rng.standard_normal(table.shape)), table)
    noisy[:, :, 80:, :] = merl.NOT_MEASURED
    return merl.write(noisy)
