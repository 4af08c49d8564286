"""Settings: every environment variable the application reads, read here and nowhere else
(documented in the README): the limits that bound the work one request may cause (so no
request can hang a worker), CORS, and where things are (the page, the caches, Chromium).

Each field's comment names its variable: ``BRDF_`` and the field's name in capitals, but
``xdg_cache_home`` (the XDG standard's own ``XDG_CACHE_HOME``). :func:`environment` is the
settings of the process's environment, for code below the API that has no application.
"""
from __future__ import annotations

import os
import re
from dataclasses import dataclass, field, fields
from pathlib import Path


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
    #: bytes of uploaded data sets kept in the store (BRDF_DATA_URL; least recently used
    #: dropped first, a quarter per client): BRDF_MAX_DATASETS_BYTES
    max_datasets_bytes: int = 256 * 1024 * 1024
    #: bytes of memory one request's computation may hold at its peak (evaluation, Monte
    #: Carlo and grids run in chunks to stay under it; more is refused before any work):
    #: BRDF_MAX_REQUEST_BYTES
    max_request_bytes: int = 1 << 30
    #: directory of the E(μ, α) tables built at start-up and shared by workers and
    #: restarts: BRDF_CACHE_DIR (empty: $XDG_CACHE_HOME/brdf-explorer or
    #: ~/.cache/brdf-explorer; unwritable: tables kept in memory only)
    cache_dir: str = ""
    #: where uploaded data sets are kept: BRDF_DATA_URL. A directory or file:// URL: every
    #: worker of one host (empty: datasets/ under the cache directory); any other fsspec
    #: URL, e.g. s3://bucket/prefix: every worker of every host (the extra [s3])
    data_url: str = ""
    #: seconds a browser or CDN may reuse a GET /api/v1 response: BRDF_CACHE_MAX_AGE
    cache_max_age: int = 3600
    #: origins allowed to GET cross-origin (embedding): BRDF_CORS_ORIGINS, comma-separated
    cors_origins: tuple[str, ...] = field(default=("*",))
    #: the page's directory, served at / and /static (a page under development elsewhere):
    #: BRDF_STATIC_DIR (empty: the installed app/static, else the checkout's static/)
    static_dir: str = ""
    #: the Chromium binary of server-side image export (SVG, PNG): BRDF_CHROMIUM (empty:
    #: the one kaleido finds)
    chromium: str = ""
    #: the compiled (numba) loops: BRDF_FAST ("0" turns them off; numpy answers)
    fast: bool = True
    #: directory of the generated and compiled loops, shared by processes: BRDF_KERNEL_DIR
    #: (empty: "kernels" in the user's cache, whatever BRDF_CACHE_DIR says — they are
    #: code, not tables —, else a temporary directory)
    kernel_dir: str = ""
    #: other origins whose pages may write (POST, PUT, PATCH, DELETE) besides the
    #: server's own: BRDF_ALLOWED_ORIGINS, comma-separated (empty: only the page itself)
    allowed_origins: tuple[str, ...] = ()
    #: seconds a request body may go without a byte before it is answered 408:
    #: BRDF_BODY_IDLE_SECONDS. A 36 MB upload at 1 Mbit/s sends a TCP segment every few
    #: ms; 15 s of silence is a stalled or hostile client.
    body_idle_seconds: float = 15.0
    #: worker processes of the heavy-work pool (app/work): BRDF_HEAVY_WORKERS
    heavy_workers: int = 1
    #: jobs that may wait for a heavy worker before a 503: BRDF_HEAVY_QUEUE
    heavy_queue: int = 4
    #: the user's cache root, under which the tables go when cache_dir is empty:
    #: XDG_CACHE_HOME (empty: ~/.cache)
    xdg_cache_home: str = ""
    #: directories of model families added without editing the application (a package
    #: with family.py each, app/model/registry.py): BRDF_MODEL_DIRS, os.pathsep-separated
    model_dirs: str = ""

    @classmethod
    def from_env(cls) -> "Settings":
        """The settings of the environment's variables; a bad value stops with an error
        naming its variable."""
        values = {}
        for f in fields(cls):
            name = variable(f.name)
            raw = os.environ.get(name)
            if raw is not None:
                values[f.name] = _PARSERS.get(f.name, _non_negative)(name, type(f.default))(raw)
        return cls(**values)

    def user_cache(self) -> Path:
        """The user's cache of the explorer: $XDG_CACHE_HOME/brdf-explorer
        (~/.cache/brdf-explorer when unset)."""
        return Path(self.xdg_cache_home or Path.home() / ".cache") / "brdf-explorer"

    def cache_directory(self) -> Path:
        """Where the E(μ, α) tables go: cache_dir, else the user's cache."""
        return Path(self.cache_dir) if self.cache_dir else self.user_cache()


def variable(name: str) -> str:
    """The environment variable of the setting ``name``."""
    return "XDG_CACHE_HOME" if name == "xdg_cache_home" else "BRDF_" + name.upper()


def environment() -> Settings:
    """The settings of the process's environment, read now (code with no application:
    the page's directory, the compiled loops, the CLI, the image renderer)."""
    return Settings.from_env()


def _text(env: str, cast):
    return lambda raw: raw


def _switch(env: str, cast):
    """A switch: "0" is off, anything else on."""
    return lambda raw: raw.strip() != "0"


def _origins(env: str, cast):
    return lambda raw: tuple(x.strip() for x in raw.split(",") if x.strip())


#: how to install fsspec and s3fs, which BRDF_DATA_URL=s3://… needs (pyproject.toml's extra)
INSTALL_S3 = "pip install 'brdf-lobe-explorer[s3]'"


def remote_scheme(location: str) -> str | None:
    """The scheme of an fsspec URL other than file:// (``s3``), None for a directory."""
    found = re.match(r"([a-zA-Z][a-zA-Z0-9+.-]*)://", str(location))      # RFC 3986's scheme
    return found.group(1) if found and found.group(1).lower() != "file" else None


def _data_url(env: str, cast):
    """A directory, or a URL whose fsspec backend is installed: a missing one stops the
    server at start-up naming the package, not the first upload with a 500."""
    def parse(raw: str):
        scheme = remote_scheme(raw)
        if scheme:
            try:
                import fsspec
                fsspec.get_filesystem_class(scheme)
            except (ImportError, ValueError) as err:
                raise ValueError(f"{env}={raw!r}: {err}; for s3:// install the extra: "
                                 f"{INSTALL_S3}") from None
        return raw
    return parse


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


def _positive(env: str, cast):
    """A parser for a duration that must be above zero (a zero timeout answers at once)."""
    def parse(raw: str):
        value = _non_negative(env, cast)(raw)
        if not value > 0:
            raise ValueError(f"{env}={raw!r}: must be positive")
        return value
    return parse


#: how each setting that is not a non-negative number is read from its variable
_PARSERS = {"cache_dir": _text, "data_url": _data_url, "static_dir": _text, "chromium": _text,
            "kernel_dir": _text, "xdg_cache_home": _text, "model_dirs": _text, "fast": _switch,
            "cors_origins": _origins, "allowed_origins": _origins, "body_idle_seconds": _positive}
