"""Directional albedo E(μ_v) = ∫_{H²} f(l, v) (n·l) dl by Monte Carlo.

``albedo_mc(brdf, mu, phi=0.0, sampler="cosine", samples=1024, seed=0)`` → E and one
standard error per μ (sample std / √N), evaluations, seconds; ValueError for a sampler
that does not support the model (``SAMPLERS[name].supports(brdf)``), an unknown name or
samples < 2. The same primary samples serve every μ, so E(μ) is a smooth curve
(docs/albedo.md §4).

References: Pharr, Jakob, Humphreys, "Physically Based Rendering", 4th ed., sec. 2.1-2.2;
Kulla & Conty 2017.
"""
from __future__ import annotations

import time
from dataclasses import asdict, dataclass

import numpy as np

from ..physics.brdf import BRDF
from ..physics.numeric import where_valid
from . import cost
from .sampling import SAMPLERS, Sampler

#: directions evaluated at once (μ values × samples): sampling and evaluating take
#: 80–180 bytes a direction (tracemalloc: uniform to VNDF, smith_numeric, Student-t with
#: direction-correlated G2), so a chunk holds ≤ ~190 MB whatever the request's size.
CHUNK_DIRECTIONS = 2 ** 20
BYTES_PER_DIRECTION = 180


@dataclass
class MonteCarloResult:
    mu: np.ndarray
    E: np.ndarray
    E_error: np.ndarray        # one standard error per μ
    evaluations: int           # BRDF evaluations
    seconds: float
    sampler: str
    samples: int
    seed: int

    def as_dict(self) -> dict:
        return asdict(self)


def weights(brdf: BRDF, sampler: Sampler, v, samples: int, seed) -> tuple:
    """(l, pdf, w) with w = f(l, v) μ_l / pdf(l), 0 below the horizon, for v of shape (k, 3)."""
    l, pdf = sampler.sample(brdf, v, samples, seed)
    vv = np.broadcast_to(v[..., None, :], l.shape)
    f = brdf.evaluate(l, vv, ("f",))["f"]
    mu_l = l[..., 2]
    w = where_valid((mu_l > 0) & (pdf > 0) & (f > 0), [f, mu_l, pdf], lambda a, b, c: a * b / c, 0.0)
    return l, pdf, w


def albedo_mc(brdf: BRDF, mu, phi: float = 0.0, sampler: str = "cosine", samples: int = 1024,
              seed: int = 0) -> MonteCarloResult:
    """E(μ) and its standard error by Monte Carlo (see the module docstring)."""
    if sampler not in SAMPLERS:
        raise ValueError(f"sampler={sampler!r} is not one of {', '.join(SAMPLERS)}")
    if samples < 2:
        raise ValueError(f"samples={samples}: at least 2 are needed for a standard error")
    chosen = SAMPLERS[sampler]
    chosen.check(brdf)
    mu = np.atleast_1d(np.asarray(mu, dtype=float))
    cost.require_evaluations(brdf, mu.size * samples,
                             min(mu.size * samples, CHUNK_DIRECTIONS) * BYTES_PER_DIRECTION,
                             "samples", f"Monte Carlo with {mu.size} μ × {samples} samples")
    t0 = time.perf_counter()
    sin_t = np.sqrt(np.maximum(0.0, 1.0 - mu * mu))
    v = np.stack([sin_t * np.cos(phi), sin_t * np.sin(phi), mu], axis=-1)
    E = np.empty_like(mu)
    E_error = np.empty_like(mu)
    rows = max(1, CHUNK_DIRECTIONS // samples)
    for start in range(0, mu.size, rows):
        if start:
            cost.check_deadline(f"Monte Carlo with {mu.size} μ × {samples} samples")
        part = slice(start, start + rows)
        # every chunk restarts the same stream: common random numbers across all μ
        _, _, w = weights(brdf, chosen, v[part], samples, seed)
        E[part] = w.mean(axis=-1)
        E_error[part] = w.std(axis=-1, ddof=1) / np.sqrt(samples)
    return MonteCarloResult(mu, E, E_error, mu.size * samples, time.perf_counter() - t0,
                            sampler, int(samples), int(seed))


__all__ = ["MonteCarloResult", "SAMPLERS", "albedo_mc", "weights"]
