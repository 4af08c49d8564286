"""A LUT as users ship it: kind, axes, channels, quantised values, and its error.

Kinds (E₁ = ∫ f cos with F = 1, E_S = the same with F = (1 − v·h)^5; single scattering):

* ``split_sum``   scale = E₁ − E_S, bias = E_S: specular = F₀·scale + F₉₀·bias (Karis 2013)
* ``dfg_filament`` x = E_S, y = E₁: specular = mix(x, y, F₀), and 1 + F₀(1/y − 1) the
  multiple-scattering energy compensation (Filament's DFG, Lagarde & Karis' form)
* ``kc_E``        E₁(μ, α) (Kulla & Conty 2017)
* ``kc_E_avg``    E_avg(α) = 2 ∫ E₁ μ dμ (one axis)

Error, per texel and as a maximum per channel, always against the converged integral
plus that integral's own bound: ``table`` (the stored float64 values), ``quantised`` (at
the texel centres after quantisation) and ``lookup`` (bilinear interpolation of the
quantised texels at the centre, half a texel along each axis and both: where linear
interpolation is furthest from the nodes)."""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from . import build

KINDS = {
    "split_sum": (("scale", "bias"), "specular = F0 * scale + F90 * bias (Karis 2013, split sum)"),
    "dfg_filament": (("dfg_x", "dfg_y"), "specular = mix(dfg_x, dfg_y, F0); energy compensation "
                                         "1 + F0 (1/dfg_y − 1) (Filament's multiple-scattering DFG)"),
    "kc_E": (("E",), "Kulla-Conty: f_ms = (1 − E(μ_l))(1 − E(μ_v)) / (π (1 − E_avg)) (Kulla & Conty 2017)"),
    "kc_E_avg": (("E_avg",), "Kulla-Conty's E_avg(α) = 2 ∫ E(μ) μ dμ (Kulla & Conty 2017)"),
}
QUANTISATIONS = {"unorm8": 1.0 / 255.0, "unorm16": 1.0 / 65535.0, "float16": 2.0 ** -11, "float32": 2.0 ** -24}


def quantise(values: np.ndarray, quantisation: str) -> np.ndarray:
    """Values as the format stores them, read back as float64."""
    if quantisation == "unorm8":
        return np.round(np.clip(values, 0.0, 1.0) * 255.0) / 255.0
    if quantisation == "unorm16":
        return np.round(np.clip(values, 0.0, 1.0) * 65535.0) / 65535.0
    if quantisation == "float16":
        return values.astype(np.float16).astype(float)
    return values.astype(np.float32).astype(float)


def upsample(q: np.ndarray, axes: int) -> np.ndarray:
    """Bilinear (linear for one axis) interpolation of texel values at the refined grid."""
    out = q
    for axis in range(axes):
        a = np.moveaxis(out, axis, 0)
        fine = np.empty((2 * a.shape[0] - 1,) + a.shape[1:])
        fine[0::2] = a
        fine[1::2] = 0.5 * (a[:-1] + a[1:])
        out = np.moveaxis(fine, 0, axis)
    return out


def per_texel(fine: np.ndarray, axes: int) -> np.ndarray:
    """Max over each texel's centre and its half-texel offsets up each axis."""
    out = fine
    for axis in range(axes):
        a = np.moveaxis(out, axis, 0)
        centre = a[0::2].copy()
        centre[:-1] = np.maximum(centre[:-1], a[1::2])
        out = np.moveaxis(centre, 0, axis)
    return out


@dataclass
class Lut:
    kind: str
    axes: list[dict]
    channels: tuple[str, ...]
    exact: np.ndarray          # converged values at the refined grid [..., channel]
    bound: np.ndarray          # their error bound
    seconds: float
    evaluations: int

    @property
    def dims(self) -> int:
        return len(self.axes)

    @property
    def table(self) -> np.ndarray:
        return self.exact[(slice(None, None, 2),) * self.dims]

    def errors(self, quantisation: str) -> dict:
        centre = (slice(None, None, 2),) * self.dims
        q = quantise(self.table, quantisation)
        table_err = self.bound[centre]
        quant_err = np.abs(q - self.table) + table_err
        lookup_fine = np.abs(upsample(q, self.dims) - self.exact) + self.bound
        lookup_err = per_texel(lookup_fine, self.dims)
        reduce = tuple(range(self.dims))
        return {"values": q,
                "table": {"max": table_err.max(axis=reduce), "per_texel": table_err},
                "quantised": {"max": quant_err.max(axis=reduce), "per_texel": quant_err},
                "lookup": {"max": lookup_err.max(axis=reduce), "per_texel": lookup_err,
                           "offsets": [[0.0] * self.dims] + [[0.5 if k == a else 0.0 for k in range(self.dims)]
                                                             for a in range(self.dims)]
                           + ([[0.5] * self.dims] if self.dims > 1 else [])},
                "step": QUANTISATIONS[quantisation]}


def make(kind: str, key: build.LobeKey, n: int, mu_axis: str, roughness_axis: str) -> Lut:
    build.check_size(n)
    channels = KINDS[kind][0]
    x = build.centres(n)
    r_axis = {"name": roughness_axis, "values": x,
              "alpha": ("r²" if roughness_axis == "roughness" else "α") + " (at least 1e-4)"}
    if kind == "kc_E_avg":
        g = build.average_grid(key, n, roughness_axis)
        return Lut(kind, [r_axis], channels, g.values[:, None], g.error[:, None], g.seconds, g.evaluations)
    mu = {"name": mu_axis, "values": x, "mu": "x²" if mu_axis == "sqrt_mu" else "x"}
    one = build.albedo_grid(key, n, mu_axis, roughness_axis, None)
    if kind == "kc_E":
        return Lut(kind, [r_axis, mu], channels, one.values[..., None], one.error[..., None],
                   one.seconds, one.evaluations)
    s = build.albedo_grid(key, n, mu_axis, roughness_axis, build.SCHLICK_P)
    if kind == "split_sum":
        exact = np.stack([one.values - s.values, s.values], axis=-1)
        bound = np.stack([one.error + s.error, s.error], axis=-1)
    else:
        exact = np.stack([s.values, one.values], axis=-1)
        bound = np.stack([s.error, one.error], axis=-1)
    return Lut(kind, [r_axis, mu], channels, exact, bound, one.seconds + s.seconds,
               one.evaluations + s.evaluations)


def orientation(dims: int) -> str:
    if dims == 1:
        return "values[i][c]: i along axes[0] (texel centres (i + 0.5)/n)"
    return ("values[i][j][c]: i along axes[0] (rows), j along axes[1] (columns), texel centres (k + 0.5)/n "
            "on both. Images: row 0 is the first row of the file (the top); uploaded as is with "
            "glTexImage2D it is t = 0.5/n, so sample at (u, v) = (axes[1] value, axes[0] value).")


def model_label(brdf) -> str:
    """The model a LUT was built for, in words from the registry entries' labels: NDF,
    masking (with its description, which states k for Schlick-GGX), G2 form."""
    return (f"{type(brdf.ndf).label}; masking {brdf.masking.name}: {brdf.masking.label} "
            f"({brdf.masking.description}); G2 {brdf.g2.name}: {brdf.g2.label}")
