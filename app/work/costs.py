"""What each heavy route's work will cost, decided before the work (issue 36).

Two places decide:

* in the server, before a job is queued (:func:`upload_seconds`): a prediction from the
  request alone, for the pool's admission (413 never fits, 503 not now);
* in the worker, before the work starts, where the model is built and its cost per
  sample can be measured without taking the server's GIL (:func:`require_view`,
  :func:`require_samples_csv`): :func:`require` refuses with 413 naming the limit and
  what would fit, or 503 + Retry-After when only what is left of the budget is short.

Costs per sample are measured by probes (CPU seconds, so a loaded moment does not
inflate them), kept per process and per model family; the prediction is multiplied by
:data:`~app.integrate.cost.SAFETY` as the rest of the server's cost checks are.
"""
from __future__ import annotations

import math
import time
from functools import lru_cache

import numpy as np

from ..config import Settings, environment
from ..datasets.tabulate import savetxt_text
from ..errors import Busy, TooLarge
from ..integrate import budget
from ..integrate.cost import SAFETY, seconds_per_evaluation

#: seconds per row of a samples-CSV upload, parsing and summary (O(rows log rows)):
#: 6.7 µs measured at 870 000 rows (1.7 s parsing, 4.2 s summary, quiet 2-core machine),
#: rounded up for a loaded one
UPLOAD_SECONDS_PER_ROW = 8e-6
#: seconds per byte of a MERL .binary upload (1.46 M cells × 3 channels, 35 MB)
UPLOAD_SECONDS_PER_BYTE = 1e-7
#: pixels across the probe of a sphere's cost: a 64-pixel image at the request's own
#: samples per pixel (the cost of a sample depends on how many share a block: a probe at
#: fewer samples underestimated the principled model 1.5× and overestimated GGX 2×)
SPHERE_PROBE_N = 64
#: rows of the probe of a samples CSV's encoding (np.savetxt, one Python call a row)
CSV_PROBE_ROWS = 20_000
#: share of the time budget what a 413 suggests ("at samples=61, n ≤ 128 would fit") is
#: predicted to take: the probes of a cost vary ~20 % from one run to the next (up to
#: 50 % at load 17 on 2 cores: a principled sphere's probe read 1.3 s, then 2.0 s), so a
#: suggestion at the very edge was refused again by the next probe, or admitted and cut
#: (tests/robustness/test_fits_margin.py: the suggestion admitted under a budget 1.2×
#: smaller, which refused it in 2 of 3 runs at the edge)
FITS_MARGIN = 0.6


def require(predicted: float, param: str, what: str, fits) -> None:
    """Refuse work predicted to take ``predicted`` seconds (before SAFETY) when it cannot
    fit: 413 beyond the whole budget, naming BRDF_MAX_SECONDS and ``fits(seconds)``
    (what would fit in that many seconds of work: FITS_MARGIN of the budget, so that
    what it names fits); 503 beyond what is left of it."""
    b = budget.current()
    if b is None:
        return
    needed = SAFETY * predicted
    if needed > b.seconds:
        raise TooLarge(param, f"{what} is predicted to take ~{needed:.1f} s, beyond the time "
                              f"budget BRDF_MAX_SECONDS={b.seconds:g}; "
                              f"{fits(FITS_MARGIN * b.seconds / SAFETY)}")
    left = b.seconds - b.elapsed()
    if needed > left:
        raise Busy(f"{what} needs ~{needed:.1f} s and this request has {max(left, 0):.1f} s of "
                   f"BRDF_MAX_SECONDS={b.seconds:g} left (the server is busy): retry",
                   retry_after=math.ceil(needed), what="time budget")


# --------------------------------------------------------------------- uploads
def upload_seconds(content: bytes) -> tuple[float, str]:
    """(predicted seconds, what would fit) of parsing and summarising an upload, from its
    bytes: rows of text, or bytes of a binary table."""
    rows = content.count(b"\n")
    if rows:
        limit = int(FITS_MARGIN * budget_seconds() / UPLOAD_SECONDS_PER_ROW)
        return rows * UPLOAD_SECONDS_PER_ROW, f"at most ~{limit} rows fit"
    return len(content) * UPLOAD_SECONDS_PER_BYTE, "a smaller file would fit"


def budget_seconds() -> float:
    """The request's whole time budget (BRDF_MAX_SECONDS)."""
    b = budget.current()
    return b.seconds if b is not None else environment().max_seconds


# --------------------------------------------------------------------- views
def _family(values: dict) -> tuple:
    """What a model's cost depends on: its choices, and which of its amounts are on
    (a lobe weighted 0 is not evaluated); not their sizes."""
    return tuple(sorted((k, v if isinstance(v, (str, bool)) or v is None else v != 0)
                        for k, v in values.items()))


@lru_cache(maxsize=128)
def _sphere_rate(family: tuple, values: tuple, environment: str, samples: int) -> float:
    """Seconds per pixel of a sphere under ``environment`` at ``samples`` per pixel for
    this model family: a probe image's CPU time (this thread) over its pixels."""
    from ..environment.sphere import environment_lighting, lit_sphere, point_light
    from ..model import make_spec
    brdf = make_spec(**dict(values)).brdf()
    lighting = (point_light(40.0, 135.0) if environment == "point"
                else environment_lighting(environment, 40.0, 135.0))
    t0 = time.thread_time()
    lit_sphere(brdf, lighting, SPHERE_PROBE_N, samples=samples)
    return (time.thread_time() - t0) / (math.pi / 4 * SPHERE_PROBE_N ** 2)


def _sphere_env(view, q, settings: Settings) -> None:
    from ..views import schemas
    values = schemas.model_values(q)
    per_pixel = 1 if q.environment == "point" else q.samples
    rate = _sphere_rate(_family(values), tuple(sorted(values.items())), q.environment, per_pixel)
    pixels = math.pi / 4 * q.n * q.n
    curves = len(getattr(q, "values", None) or [None])
    predicted = curves * pixels * rate

    def fits(seconds: float) -> str:
        n = int(math.sqrt(seconds / curves / rate * 4 / math.pi))
        if q.environment != "point":
            samples = int(per_pixel * seconds / predicted)     # nearly linear in samples
            if samples >= 4:
                return f"at n={q.n}, samples ≤ {samples} would fit; at samples={per_pixel}, n ≤ {n}"
        return f"at samples={per_pixel}, n ≤ {n} would fit"
    require(predicted, "samples" if q.environment != "point" else "n",
            f"a sphere of {q.n}×{q.n} px × {per_pixel} samples", fits)


#: the views whose work runs in the heavy pool, each with its cost check (None: the
#: view's own limits and checks bound it; the pool cuts it at the budget)
VIEW_COSTS = {"sphere_env": _sphere_env, "samples": None}


def require_view(view, q, settings: Settings) -> None:
    check = VIEW_COSTS.get(view.name)
    if check is not None:
        check(view, q, settings)


# --------------------------------------------------------------------- exports
@lru_cache(maxsize=1)
def _csv_seconds_per_row() -> float:
    """Seconds np.savetxt takes per row of five %.17g numbers, in this process: timed
    through the export's own savetxt_text, whose closed buffer does not leave the probe's
    1.9 MB of text to the cycle collector (tabulate.savetxt_text)."""
    rows = np.random.default_rng(0).uniform(0.0, 90.0, (CSV_PROBE_ROWS, 5))
    t0 = time.thread_time()
    savetxt_text(rows, fmt="%.17g", delimiter=",")
    return (time.thread_time() - t0) / CSV_PROBE_ROWS


def require_samples_csv(brdf, n_theta: int, n_phi: int) -> None:
    """The model's samples CSV (n_theta² × n_phi rows): evaluations and encoding."""
    per_row = seconds_per_evaluation(brdf) + _csv_seconds_per_row()
    rows = n_theta * n_theta * n_phi

    def fits(seconds: float) -> str:
        return f"at n_theta={n_theta}, n_phi ≤ {max(int(seconds / per_row / n_theta ** 2), 0)} would fit"
    require(rows * per_row, "n_phi", f"a samples CSV of {rows} rows", fits)
