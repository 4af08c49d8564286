"""Settings: limits and CORS, from environment variables (documented in the README).

Every limit bounds the work one request may cause, so no request can hang a worker.
"""
from __future__ import annotations

import os
from dataclasses import dataclass, field, fields


def _env(name: str, default, cast):
    raw = os.environ.get(name)
    return default if raw is None else cast(raw)


@dataclass(frozen=True)
class Settings:
    #: points of a 1-D curve (ndf, g1, lobe): BRDF_MAX_CURVE_POINTS
    max_curve_points: int = 4001
    #: n_theta × n_phi of a 2-D grid (lobe3d): BRDF_MAX_GRID_POINTS
    max_grid_points: int = 250_000
    #: direction pairs in one GET /eval (query string): BRDF_MAX_QUERY_LIST
    max_query_list: int = 4096
    #: direction pairs in one POST /eval: BRDF_MAX_BATCH. 250 000 pairs take ~3.5 s and
    #: ~0.5 GB (parse, evaluate, encode); 10⁶ took 11 s of CPU and 0.9 GB, past the
    #: time budget with no way to cut it (bench/worst_case.py)
    max_batch: int = 250_000
    #: μ values in one albedo request: BRDF_MAX_ALBEDO_POINTS
    max_albedo_points: int = 257
    #: sampled directions in one /samples request (~50 bytes each in JSON): BRDF_MAX_SAMPLES
    max_samples: int = 200_000
    #: Monte Carlo BRDF evaluations (μ values × samples) of one albedo request:
    #: BRDF_MAX_MC_EVALUATIONS. Measured 0.35-3.6 M/s (sampler and NDF; numpy), so the
    #: worst allowed request takes ~6 s on a loaded machine.
    max_mc_evaluations: int = 2_097_152
    #: largest budget of one /tradeoff request (max_budget: Monte Carlo samples per μ;
    #: Gauss orders stop at 64 anyway): BRDF_MAX_TRADEOFF_SAMPLES. At 9 μ the top points
    #: of the four samplers take ~0.4 s together (GGX, measured); more μ are stopped by
    #: the time budget, with a note.
    max_tradeoff_samples: int = 65_536
    #: models compared in one POST /figures/{kind}: BRDF_MAX_COMPARE_MODELS
    max_compare_models: int = 8
    #: width × height × scale² of one exported PNG/SVG: BRDF_MAX_EXPORT_PIXELS (4096²)
    max_export_pixels: int = 16_777_216
    #: wall-clock seconds one request may compute: BRDF_MAX_SECONDS. Adaptive work
    #: (albedo refinement) stops before it would run past this and says so.
    max_seconds: float = 10.0
    #: integrand evaluations the worst case of one albedo request may need (ORDER_MAX at
    #: every μ): BRDF_MAX_EVALUATIONS; above it the request is refused before any work.
    max_evaluations: int = 200_000_000
    #: bytes of the query string: BRDF_MAX_QUERY_BYTES (414 above it; use POST /eval)
    max_query_bytes: int = 16_384
    #: bytes of a request body: BRDF_MAX_BODY_BYTES (413 above it, before any parsing): a
    #: full batch of four full-precision lists is ~21 MB
    max_body_bytes: int = 24 * 1024 * 1024
    #: bytes of one uploaded measured data set (POST /api/v1/datasets; one MERL .binary
    #: is 34 992 012 bytes, plus multipart overhead): BRDF_MAX_UPLOAD_BYTES
    max_upload_bytes: int = 36_000_000
    #: bytes of uploaded data sets kept in memory (least recently used dropped first):
    #: BRDF_MAX_DATASETS_BYTES
    max_datasets_bytes: int = 256 * 1024 * 1024
    #: bytes of memory one request's computation may hold at its peak (evaluation, Monte
    #: Carlo and grids run in chunks to stay under it; more is refused before any work):
    #: BRDF_MAX_REQUEST_BYTES
    max_request_bytes: int = 1 << 30
    #: directory of the E(μ, α) tables built at start-up and shared by workers and
    #: restarts: BRDF_CACHE_DIR (empty: $XDG_CACHE_HOME/brdf-explorer or
    #: ~/.cache/brdf-explorer; unwritable: tables kept in memory only)
    cache_dir: str = ""
    #: seconds a browser or CDN may reuse a GET /api/v1 response: BRDF_CACHE_MAX_AGE
    cache_max_age: int = 3600
    #: origins allowed to GET cross-origin (embedding): BRDF_CORS_ORIGINS, comma-separated
    cors_origins: tuple[str, ...] = field(default=("*",))

    @classmethod
    def from_env(cls) -> "Settings":
        values = {}
        for f in fields(cls):
            env = "BRDF_" + f.name.upper()
            if f.name == "cache_dir":
                values[f.name] = os.environ.get(env, "")
            elif f.name == "cors_origins":
                values[f.name] = _env(env, ("*",), lambda s: tuple(x.strip() for x in s.split(",") if x.strip()))
            else:
                values[f.name] = _env(env, f.default, _non_negative(env, type(f.default)))
        return cls(**values)


def _non_negative(env: str, cast):
    """A parser for one numeric setting that names the variable when its value is bad
    (a typo must stop the server at start-up, not surface as a 500 later)."""
    def parse(raw: str):
        try:
            value = cast(raw)
        except ValueError:
            raise ValueError(f"{env}={raw!r}: expected a {cast.__name__}") from None
        if not value >= 0:
            raise ValueError(f"{env}={raw!r}: must not be negative")
        return value
    return parse
