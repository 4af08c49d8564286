"""The relative cost of a model: CPU time of f on fixed direction pairs, measured once
per process and kind of model (docs/advise.md §4)."""
from __future__ import annotations

import time
from functools import lru_cache

import numpy as np

from ..integrate.cache import Keyed, freeze
from ..model import COMMON_PARAMS, OPTIONS, SUB_OPTIONS, choice_param_names, make_spec

#: f evaluations timed per run (below fast.PARALLEL_MIN: one thread), at least this many
#: runs per model (the minimum is kept), and the CPU seconds after which a slow model
#: (smith_numeric: 0.3 s a run) stops repeating.
COST_PAIRS = 16_384
COST_REPEATS = 5
#: ... and runs go on until this much CPU time is spent: a single 0.3 ms run is off by up
#: to 23 % on a loaded machine, the minimum over ~60 runs by −0.3 % .. +0.5 % (12 repeats).
COST_SECONDS_MIN = 0.02
COST_SECONDS_CAP = 0.25
COST_SEED = 0
#: α of the timed models (cost does not depend on it but through smith_numeric's orders).
COST_ALPHA = 0.3
#: Models timed and kept per process (a few floats each).
COST_CACHE_ENTRIES = 512
#: Smallest CPU time a timing reports: time.thread_time ticks in 1 µs or coarser, so a
#: run below a tick can read 0 and a relative cost would divide by it (here and for the
#: albedo methods' wall times); 1 ns is far below
#: any real run (the fastest measured, GGX compiled: 0.44 ms).
COST_SECONDS_FLOOR = 1e-9
#: A choice counts as cheaper when it costs below this fraction of the current model.
#: The cost of one model measured 12 times on a loaded 2-core machine spread by −9 % .. +1 %
#: (GGX compiled, 0.31 ms) and −3 % .. +7 % (Karis, 2.6 ms): 0.85 keeps an equal-cost
#: choice (separable G2, compiled) from being recommended on noise.
CHEAPER_BELOW = 0.85
#: Continuous values that do not change what code runs (the cost key leaves them out).
_CONTINUOUS = {"alpha", "alpha_y", "roughness", "anisotropy", "aniso_map", "kd", "f0", "f90",
               "ior", "k", "alpha2", "lobe_mix"}


def cost_key(model: dict) -> tuple:
    values = make_spec(**model).values
    kept = {k: v for k, v in values.items()
            if k not in _CONTINUOUS and isinstance(v, (str, int, float)) and k in _model_names()}
    kept["two_lobes"] = bool(values.get("lobe_mix")) and values.get("alpha2") is not None
    return tuple(sorted(kept.items()))


@lru_cache(maxsize=1)
def _model_names() -> frozenset:
    return frozenset(OPTIONS) | frozenset(SUB_OPTIONS) | {p.name for p in COMMON_PARAMS} \
        | frozenset(choice_param_names())


@lru_cache(maxsize=1)
def _pairs() -> tuple[np.ndarray, np.ndarray]:
    """COST_PAIRS fixed (l, v), uniform over the upper hemisphere."""
    rng = np.random.default_rng(COST_SEED)
    u = rng.random((2, COST_PAIRS, 2))
    mu, phi = u[..., 0], 2.0 * np.pi * u[..., 1]
    s = np.sqrt(1.0 - mu * mu)
    w = np.stack([s * np.cos(phi), s * np.sin(phi), mu], axis=-1)
    freeze(w)
    return w[0], w[1]


@lru_cache(maxsize=COST_CACHE_ENTRIES)
def _seconds(kind: Keyed) -> float:
    """Least CPU seconds of f at the fixed pairs over the runs, for one kind of model
    (``kind.key``); the first model of that kind seen (``kind.value``) is the one timed
    (continuous values do not matter)."""
    brdf = make_spec(**kind.value).at_alpha(COST_ALPHA).brdf()
    l, v = _pairs()
    brdf.evaluate(l, v)                          # warm-up: numba compiles on first use
    runs, spent = [], 0.0
    while not runs or (spent < COST_SECONDS_CAP
                       and (len(runs) < COST_REPEATS or spent < COST_SECONDS_MIN)):
        t0 = time.thread_time()
        brdf.evaluate(l, v)
        runs.append(time.thread_time() - t0)
        spent += runs[-1]
    return max(float(np.min(runs)), COST_SECONDS_FLOOR)


def seconds_per_batch(model: dict) -> float:
    return _seconds(Keyed(model, cost_key(model)))
