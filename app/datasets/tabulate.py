"""A model as data: its MERL table and its samples CSV, for renderers and other tools
that read those formats (and for the tests, which write files from known models)."""
from __future__ import annotations

import io
import time

import numpy as np

from ..errors import Busy, TooLarge
from ..integrate import budget
from ..physics.vectors import direction_deg
from ..physics.brdf import BRDF
from ..physics.numeric import where_valid
from ..quantities import evaluate, rusinkiewicz_directions
from . import merl

#: direction pairs timed to predict a whole table's time before it is started
CALIBRATION_PAIRS = 4096
#: θ_h rows of the MERL table evaluated at once: 10 rows are 162 000 direction pairs,
#: ~60 MB of temporaries in the numpy path, instead of ~0.5 GB for the whole table.
ROWS_PER_CHUNK = 10


def merl_table(brdfs: list[BRDF]) -> np.ndarray:
    """f[channel, θ_h, θ_d, φ_d] of one model per channel (R, G, B), at the cell centres
    (merl.centres_deg), with φ_h = 0 (isotropic models do not depend on it). Cells with
    l or v below the horizon are "not measured", as in the published files; so are the
    cells where f diverges (both directions grazing), which the format cannot hold."""
    theta_h, theta_d, phi_d = merl.centres_deg()
    _affordable(brdfs)
    table = np.empty((len(brdfs),) + merl.DIMS)
    for start in range(0, merl.DIMS[0], ROWS_PER_CHUNK):
        rows = theta_h[start:start + ROWS_PER_CHUNK]
        l, v = rusinkiewicz_directions(rows[:, None, None], 0.0, theta_d[None, :, None],
                                       phi_d[None, None, :])
        l, v = np.broadcast_arrays(l, v)
        above = (l[..., 2] >= 0.0) & (v[..., 2] >= 0.0)
        for c, brdf in enumerate(brdfs):
            f = np.full(above.shape, merl.NOT_MEASURED)
            f[above] = brdf.f(l[above], v[above])
            table[c, start:start + len(rows)] = where_valid(np.isfinite(f), [f], lambda x: x,
                                                            merl.NOT_MEASURED)
    return table


def _affordable(brdfs: list[BRDF]) -> None:
    """Before any work, refuse a table the request's time budget (BRDF_MAX_SECONDS) would
    not cover, its time predicted from a few thousand pairs: 413 beyond the whole budget
    (no retry helps), 503 beyond what is left of it."""
    request_budget = budget.current()
    if request_budget is None:
        return
    spent_before = request_budget.elapsed()         # waiting, or earlier work of this request
    rng = np.random.default_rng(0)
    l, v = (direction_deg(rng.uniform(0, 90, CALIBRATION_PAIRS), rng.uniform(0, 360, CALIBRATION_PAIRS))
            for _ in range(2))
    start = time.perf_counter()
    for brdf in brdfs:
        brdf.f(l, v)
    # ~76 % of the cells are above the horizon (the others are not evaluated)
    predicted = (time.perf_counter() - start) * 0.76 * merl.CELLS / CALIBRATION_PAIRS
    if request_budget.elapsed() - spent_before + predicted > request_budget.seconds:
        raise TooLarge("model", f"a MERL table of this model takes ~{predicted:.1f} s here, beyond "
                                f"the request's whole time budget (BRDF_MAX_SECONDS="
                                f"{request_budget.seconds:g}): a model with closed-form masking "
                                f"and one lobe is faster, or the server's budget can be raised")
    if not request_budget.affords(predicted):
        raise Busy(f"a MERL table of this model takes ~{predicted:.1f} s here, more than is left "
                   f"of the request's time budget (BRDF_MAX_SECONDS={request_budget.seconds:g})",
                   retry_after=int(predicted) + 1, what="MERL export")


def merl_bytes(brdf: BRDF) -> bytes:
    """A MERL .binary file of one model, the same in R, G and B."""
    return merl.write(merl_table([brdf]).repeat(3, axis=0))


#: columns of the samples CSV (the reader's samples format)
SAMPLE_COLUMNS = ("theta_i_deg", "phi_i_deg", "theta_o_deg", "phi_o_deg", "f")


def samples_csv(brdf: BRDF, theta_deg: np.ndarray, phi_deg: np.ndarray) -> str:
    """f at every pair (θ_i, φ_i = 0; θ_o, φ_o) of the grids, as the samples CSV.
    Pairs where f diverges (both directions grazing) are left out: CSV has no inf."""
    ti, to, po = np.meshgrid(theta_deg, theta_deg, phi_deg, indexing="ij")
    ti, to, po = ti.ravel(), to.ravel(), po.ravel()
    f = evaluate(brdf, ti, 0.0, to, po, ("f",))["f"]
    keep = np.isfinite(f)
    rows = np.column_stack([ti[keep], np.zeros(keep.sum()), to[keep], po[keep], f[keep]])
    return savetxt_text(rows, fmt="%.17g", delimiter=",", header=",".join(SAMPLE_COLUMNS),
                        comments="")


def savetxt_text(rows: np.ndarray, **options) -> str:
    """``np.savetxt(file, rows, **options)``'s text, its buffer closed before it returns.
    savetxt's writer (numpy's WriteWrap) holds the file it is given in a reference cycle,
    which only the cycle collector frees; an open StringIO keeps its whole text until
    then. A heavy-pool worker's job leaves ~27 new tracked objects, so the collector ran
    every ~22 jobs (its first generation's threshold is 700): each samples CSV (16 MB at
    91² × 60 rows) stayed until then, RSS +15.6 MB a request up to ~600 MB (issue 36)."""
    with io.StringIO() as out:
        np.savetxt(out, rows, **options)
        return out.getvalue()
