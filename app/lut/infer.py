"""What code generated this LUT? The conventions of an uploaded table, inferred by fit.

A split-sum or DFG table is E₁(μ, α) and E_S(μ, α) (table.py) sampled on some grid and
stored some way. The conventions engines differ in are finitely many, so every
combination is a hypothesis, and each is *built* — the integrals at the positions that
hypothesis puts the texels, for the upload's own size n — and compared with the upload:

* model:  α = r² or α = r (``roughness`` / ``alpha``), μ = x or μ = x² (``mu`` /
  ``sqrt_mu``), texel centres x = (i + ½)/n or edges x = i/(n − 1) (per axis), G2
  separable or height-correlated (Heitz 2014, eq. 98/99; plus the query's own G2 when
  it is another), split form (scale, bias) (Karis 2013) or DFG (x = E_S, y = E₁;
  Filament's "Physically Based Rendering in Filament", §5.3.4.7 and §9.5);
* arrangement of the stored array: which axis runs along the rows, each axis
  increasing or decreasing with the index (the eight symmetries of the square), the two
  channels as named or swapped;
* storage (not fitted: read from the values): unit floats, 0–255 or 0–65535 integers.

The fit is the RMS difference over sampled *interior* texels (the first and last row
and column are where generators clamp μ = 0 and α = 0 differently, so they take no part
in the choice). The answer states the best hypothesis, its residual, and for each
convention the best hypothesis that differs in it alone or with others (its residual and
the ratio to the best): a ratio near 1 says that convention was not decided.
"""
from __future__ import annotations

import itertools
from dataclasses import dataclass
from functools import lru_cache

import numpy as np

from ..errors import ParameterError
from ..integrate.albedo import albedo, albedo_average
from . import build

#: texel positions along an axis of n texels
PLACEMENTS = {"centres": lambda n: (np.arange(n) + 0.5) / n,
              "edges": lambda n: np.arange(n) / (n - 1.0)}
#: G2 forms every check tries (the query's own is added when it is another)
G2_CANDIDATES = ("separable", "height_correlated")
#: the two ways a two-channel table holds E₁ and E_S
SPLIT_FORMS = {"split_sum": lambda e1, es: (e1 - es, es), "dfg_filament": lambda e1, es: (es, e1)}
#: interior texels sampled per axis for the fit (all of them up to this many)
SAMPLE_PER_AXIS = 12
#: texels per axis of the error map (all of them up to this many, else evenly sampled)
ERROR_MAP_PER_AXIS = 16
#: quadrature tolerance of the candidate tables: 50× below the 8-bit step, 10× below the
#: differences between hypotheses that matter least (centres against edges at n = 256)
FIT_TOL = 1e-5
#: the smallest table whose conventions can be inferred (two interior texels per axis)
SIZE_MIN_INFER = 4


def sample(n: int, k: int, interior: bool = True) -> np.ndarray:
    """Indices symmetric under i ↦ n − 1 − i (so flips and transposes map the sample
    onto itself): all of them when there are at most k, else k spread evenly."""
    lo = 1 if interior else 0
    if n - 2 * lo <= k:
        return np.arange(lo, n - lo)
    half = np.unique(np.floor(np.linspace(lo, (n - 1) / 2.0, (k + 1) // 2)).astype(int))
    return np.unique(np.concatenate([half, n - 1 - half]))


def storage(values: np.ndarray, png_bits: int | None) -> tuple[np.ndarray, str]:
    """Unit values and how they were stored (PNGs: unsigned normalised by their depth)."""
    if png_bits is not None:
        return values, f"PNG unorm{png_bits} (integers / {2 ** png_bits - 1})"
    top = float(values.max())
    if top > 255.5:
        return values / 65535.0, "numbers 0–65535 (unorm16 integers not divided by 65535)"
    if top > 1.5:
        return values / 255.0, "numbers 0–255 (unorm8 integers not divided by 255)"
    steps = values * 255.0
    if np.allclose(steps, np.round(steps), atol=1e-6):
        return values, "unit floats on the 1/255 grid (an 8-bit table)"
    return values, "unit floats"


@dataclass(frozen=True)
class Model:
    """A hypothesis about how the table was computed."""
    g2: str
    roughness_axis: str
    mu_axis: str
    roughness_texels: str
    mu_texels: str
    split: str | None


@dataclass(frozen=True)
class Arrangement:
    """A hypothesis about how the computed table was stored."""
    rows: str                 # "roughness" or "mu" (2-D), "roughness" (1-D)
    roughness_increasing: bool
    mu_increasing: bool
    channels_swapped: bool

    def canonical(self, values: np.ndarray, dims: int) -> np.ndarray:
        """The upload rearranged to rows roughness ascending, columns μ ascending."""
        v = values
        if dims == 2 and self.rows == "mu":
            v = v.transpose(1, 0, 2)
        if not self.roughness_increasing:
            v = v[::-1]
        if dims == 2 and not self.mu_increasing:
            v = v[:, ::-1]
        return v[..., ::-1] if self.channels_swapped else v


def _positions(n: int, axis: str, texels: str, of) -> np.ndarray:
    return of(axis, PLACEMENTS[texels](n))


def exact(key: build.LobeKey, alphas: np.ndarray, mus: np.ndarray | None, schlick: bool,
          tol: float) -> tuple[np.ndarray, np.ndarray]:
    """E₁ and E_S (zeros unless ``schlick``) at alphas × mus, or E_avg at alphas (mus None),
    by the project's adaptive quadrature (app/integrate/albedo.py), with their bounds."""
    if mus is None:
        rows = [albedo_average(key.lobe(float(a), None), tol=tol) for a in alphas]
        return np.array([[r[0]] for r in rows]), np.array([[r[1]] for r in rows])
    values, bounds = [], []
    for a in alphas:
        one = albedo(key.lobe(float(a), None), mus, tol=tol)
        s = albedo(key.lobe(float(a), build.SCHLICK_P), mus, tol=tol) if schlick else None
        values.append(np.stack([one.E, s.E if s else 0 * one.E], axis=-1))
        bounds.append(np.stack([one.E_error, s.E_error if s else 0 * one.E], axis=-1))
    return np.array(values), np.array(bounds)


@lru_cache(maxsize=build.CACHE_ENTRIES)
def candidates(key: build.LobeKey, n: int, dims: int, schlick: bool) -> dict:
    """E₁ (and E_S) at the sampled texels under every (α map, μ map, placement): one
    quadrature over the union of their positions, shared by all arrangements."""
    idx = sample(n, SAMPLE_PER_AXIS)
    r_sets = {(a, t): _positions(n, a, t, build.alpha_of)[idx]
              for a in build.ROUGHNESS_AXES for t in PLACEMENTS}
    m_sets = {(a, t): _positions(n, a, t, build.mu_of)[idx] for a in build.MU_AXES for t in PLACEMENTS}
    alphas = np.unique(np.concatenate(list(r_sets.values())))
    mus = np.unique(np.concatenate(list(m_sets.values()))) if dims == 2 else None
    values, _ = exact(key, alphas, mus, schlick, FIT_TOL)
    out = {}
    for (ra, rt), a in r_sets.items():
        rows = values[np.searchsorted(alphas, a)]
        if dims == 1:
            out[(ra, None, rt, None)] = rows
            continue
        for (ma, mt), m in m_sets.items():
            out[(ra, ma, rt, mt)] = rows[:, np.searchsorted(mus, m)]
    return out


def channels_of(kind_channels: int, e: np.ndarray, split: str | None) -> np.ndarray:
    """The table's channels from (E₁, E_S) under a split form (E₁ alone for one channel)."""
    if kind_channels == 1:
        return e[..., :1]
    return np.stack(SPLIT_FORMS[split](e[..., 0], e[..., 1]), axis=-1)


def arrangements(dims: int, channels: int) -> list[Arrangement]:
    rows = ("roughness", "mu") if dims == 2 else ("roughness",)
    mu_dirs = (True, False) if dims == 2 else (True,)
    swaps = (False, True) if channels == 2 else (False,)
    return [Arrangement(r, ri, mi, s) for r, ri, mi, s in itertools.product(rows, (True, False), mu_dirs, swaps)]


def models(dims: int, channels: int, g2s: tuple[str, ...]) -> list[Model]:
    mu_axes = build.MU_AXES if dims == 2 else (None,)
    texels = tuple(PLACEMENTS)
    mu_texels = texels if dims == 2 else (None,)
    splits = tuple(SPLIT_FORMS) if channels == 2 else (None,)
    return [Model(*m) for m in itertools.product(g2s, build.ROUGHNESS_AXES, mu_axes, texels, mu_texels, splits)]


#: the conventions a hypothesis fixes, each with how to read it off (model, arrangement)
CONVENTIONS = {
    "g2": lambda m, a: m.g2,
    "alpha_mapping": lambda m, a: "alpha = r^2" if m.roughness_axis == "roughness" else "alpha = r",
    "mu_mapping": lambda m, a: None if m.mu_axis is None else ("mu = x" if m.mu_axis == "mu" else "mu = x^2"),
    "roughness_texels": lambda m, a: m.roughness_texels,
    "mu_texels": lambda m, a: m.mu_texels,
    "split_form": lambda m, a: m.split,
    "axis_order": lambda m, a: None if m.mu_axis is None else f"rows {a.rows}",
    "roughness_direction": lambda m, a: "increasing with the index" if a.roughness_increasing else "decreasing",
    "mu_direction": lambda m, a: None if m.mu_axis is None else
                                 ("increasing with the index" if a.mu_increasing else "decreasing"),
    "channels": lambda m, a: "swapped" if a.channels_swapped else "as named",
}


def describe(m: Model, a: Arrangement) -> dict:
    return {name: read(m, a) for name, read in CONVENTIONS.items() if read(m, a) is not None}


def fit(values: np.ndarray, keys: dict[str, build.LobeKey], dims: int) -> list[tuple[float, float, Model, Arrangement]]:
    """Every hypothesis with its RMS and max residual over the sampled interior texels,
    best first. ``values``: unit values [n][n][c] (or [n][c]); ``keys``: G2 → lobe."""
    n, channels = values.shape[0], values.shape[-1]
    idx = sample(n, SAMPLE_PER_AXIS)
    pick = np.ix_(idx, idx) if dims == 2 else (idx,)
    stored = {a: a.canonical(values, dims)[pick] for a in arrangements(dims, channels)}
    built = {g2: candidates(key, n, dims, channels == 2) for g2, key in keys.items()}
    out = []
    for m in models(dims, channels, tuple(keys)):
        table = channels_of(channels, built[m.g2][(m.roughness_axis, m.mu_axis, m.roughness_texels, m.mu_texels)],
                            m.split)
        for a, v in stored.items():
            d = v - table
            out.append((float(np.sqrt(np.mean(d * d))), float(np.max(np.abs(d))), m, a))
    out.sort(key=lambda t: t[0])
    return out


def margins(ranked: list) -> dict:
    """For each convention, the best hypothesis that names it otherwise: its value, its
    residual and that residual over the best one's (large: decided; near 1: not)."""
    best_rms, _, m0, a0 = ranked[0]
    chosen = describe(m0, a0)
    out = {}
    for name, value in chosen.items():
        alt = next((r for r in ranked[1:] if describe(r[2], r[3]).get(name) != value), None)
        if alt is not None:
            out[name] = {"chosen": value, "runner_up": describe(alt[2], alt[3])[name],
                         "runner_up_residual_rms": alt[0], "ratio": ratio(alt[0], best_rms)}
    return out


def ratio(a: float, b: float) -> float | None:
    """a/b, None when b is 0 (an exact fit: any alternative is infinitely worse)."""
    return a / b if b > 0 else None


def check_size(n: int) -> None:
    if n < SIZE_MIN_INFER:
        raise ParameterError("body", f"the uploaded LUT is {n} texels per axis; its conventions are inferred "
                                     f"from its interior texels, which needs n ≥ {SIZE_MIN_INFER}", loc="body")


def error_map(canonical: np.ndarray, key: build.LobeKey, m: Model, dims: int) -> dict:
    """The upload (rearranged to the inferred conventions) read with bilinear filtering at
    its own resolution against the integral at the same positions: per texel the max over
    its centre and the points half-way to the next texel along each axis and both (where
    linear interpolation is furthest from the nodes), at up to ERROR_MAP_PER_AXIS texels
    per axis (their indices given)."""
    n, channels = canonical.shape[0], canonical.shape[-1]
    idx = sample(n, ERROR_MAP_PER_AXIS, interior=False)
    xr = PLACEMENTS[m.roughness_texels](n)

    def fine(x, i):  # the texel's centre and the half-way point to the next (when there is one)
        return [x[i]] + ([0.5 * (x[i] + x[i + 1])] if i + 1 < n else [])

    r_pos = [fine(xr, i) for i in idx]
    alphas = build.alpha_of(m.roughness_axis, np.array([p for ps in r_pos for p in ps]))
    if dims == 2:
        xm = PLACEMENTS[m.mu_texels](n)
        m_pos = [fine(xm, j) for j in idx]
        mus = build.mu_of(m.mu_axis, np.array([p for ps in m_pos for p in ps]))
    else:
        m_pos, mus = [[0.0]], None
    e, bound = exact(key, alphas, mus, channels == 2, build.LUT_TOL)
    ref = channels_of(channels, e, m.split)
    # a channel's bound: E₁'s plus E_S's (scale = E₁ − E_S has both; a bound, not the least)
    ref_bound = np.repeat(bound.sum(axis=-1, keepdims=True), channels, axis=-1)
    per_texel = np.zeros((len(idx), len(idx) if dims == 2 else 1, channels))
    bound_max = np.zeros(channels)
    r0 = np.cumsum([0] + [len(p) for p in r_pos])
    c0 = np.cumsum([0] + [len(p) for p in m_pos])
    for a, i in enumerate(idx):
        for b, j in enumerate(idx if dims == 2 else [0]):
            for di in range(len(r_pos[a])):
                for dj in range(len(m_pos[b])):
                    rows = [i, i + di] if di else [i]
                    if dims == 2:
                        cols = [j, j + dj] if dj else [j]
                        got = np.mean([canonical[r, c] for r in rows for c in cols], axis=0)
                    else:
                        got = np.mean([canonical[r] for r in rows], axis=0)
                    want = ref[r0[a] + di, c0[b] + dj]
                    per_texel[a, b] = np.maximum(per_texel[a, b], np.abs(got - want))
                    bound_max = np.maximum(bound_max, ref_bound[r0[a] + di, c0[b] + dj])
    if dims == 1:
        per_texel = per_texel[:, 0]
    return {"indices": idx, "per_texel": per_texel, "max": per_texel.max(axis=tuple(range(dims))),
            "reference_bound": bound_max,
            "reference": f"adaptive Gauss quadrature of E(μ) (tol {build.LUT_TOL:g}) at the inferred "
                         "positions; bilinear: the mean of the neighbouring texels"}
