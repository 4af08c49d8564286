"""What a data set holds, in numbers: size, channels, coverage, value range, and for
BRDF data its reciprocity error and directional albedo E(μ) with an error bar.

E(μ_v) = ∫ f(l, v) (n·l) dl (Kulla & Conty 2017) is ∫∫ f dx dy over the unit disk of
projected directions l = (x, y, √(1 − x² − y²)): the cosine is the Jacobian. The
midpoint rule in (ρ², φ) gives every point the same weight, so E = π · mean(f). The data
are known only at their cells or samples, so E carries two errors, stated apart and
added: the interpolation error (nearest-cell against linear interpolation of the same
data) and the quadrature error (the grid against one of half the resolution); missing
values count fully into the error bar.
"""
from __future__ import annotations

import numpy as np
from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator
from scipy.spatial import ConvexHull, QhullError

from ..errors import TooLarge
from ..integrate import budget
from . import merl
from .dataset import BrdfData, TermData, angles_deg

#: cosines μ_v of the view directions at which E is given for a MERL table
MU = np.round(np.linspace(0.1, 1.0, 10), 6)
#: (u, φ_h) midpoint grid of a MERL table's albedo integral over the half vector, u =
#: √(θ_h / 90°) as the table indexes θ_h: two nodes per table cell in θ_h, so the grid is
#: as fine as the table at the peak (the first cell spans 0.011°) however sharp the lobe;
#: the error estimate uses half of it
GRID_MERL = (180, 180)
GRID_SAMPLES = (48, 96)
#: a view direction of a samples CSV is integrated if it has this many samples whose
#: projected directions span this fraction of the unit disk (else E is not given there)
MIN_GROUP, MIN_COVER = 32, 0.75
#: view directions of a samples CSV integrated at most (evenly spread in μ_v)
MAX_GROUPS = 10
#: samples of one view direction triangulated at most (a fixed-seed subset of larger
#: groups): the integration grid has 48 × 96 points, so more samples than this refine
#: nothing the error estimate (from the same subset) does not already state, and a
#: Delaunay triangulation of a whole 10⁶-sample group would cost seconds
MAX_TRIANGULATED = 20_000


def summarize(data) -> dict:
    out = {"format": data.format, "bytes": data.size, "kind": data.kind,
           "channels": list(data.channels), "count": int(data.count)}
    if isinstance(data, TermData):
        return {**out, **_term(data)}
    measured = data.measured()
    values = data.table.reshape(len(data.channels), -1) if data.table is not None else data.f
    out["fraction_measured"] = float(measured.mean())
    out["range"] = {c: [float(values[k][measured].min()), float(values[k][measured].max())]
                    if measured.any() else None for k, c in enumerate(data.channels)}
    out["reciprocity"] = _reciprocity_table(data) if data.table is not None else _reciprocity_samples(data)
    out["albedo"] = _albedo_table(data) if data.table is not None else _albedo_samples(data)
    return out


def _disk(n_s: int, n_phi: int) -> np.ndarray:
    """Midpoints of the (ρ², φ) grid as directions l (n_s·n_phi, 3)."""
    s = (np.arange(n_s) + 0.5) / n_s
    phi = (np.arange(n_phi) + 0.5) * 2.0 * np.pi / n_phi
    rho = np.sqrt(s)[:, None]
    x, y = rho * np.cos(phi), rho * np.sin(phi)
    z = np.broadcast_to(np.sqrt(1.0 - s)[:, None], x.shape)
    return np.stack([x, y, z], axis=-1).reshape(-1, 3)


def _half_grid(n_u: int, n_phi: int, v: np.ndarray) -> tuple[np.ndarray, np.ndarray]:
    """(l, weight) with E = Σ f(l, v) · weight: the integral ∫ f (n·l) dl taken over the
    half vector h, dl = 4 (v·h) dh (Walter et al. 2007, eq. 14), h at the midpoints of
    a grid in (u = √(2θ_h/π), φ_h), dθ_h = π u du. Nodes whose l is below the horizon
    (or h facing away from v) weigh 0: outside the integral, not unmeasured."""
    u = (np.arange(n_u) + 0.5) / n_u
    phi = (np.arange(n_phi) + 0.5) * 2.0 * np.pi / n_phi
    theta = 0.5 * np.pi * u * u
    st = np.sin(theta)[:, None]
    h = np.stack(np.broadcast_arrays(st * np.cos(phi), st * np.sin(phi), np.cos(theta)[:, None]),
                 axis=-1).reshape(-1, 3)
    vh = h @ v
    l = 2.0 * vh[:, None] * h - v
    jac = np.broadcast_to((np.pi * u * np.sin(theta))[:, None], (n_u, n_phi)).ravel()
    weight = np.where((l[:, 2] > 0) & (vh > 0), l[:, 2] * 4.0 * vh * jac, 0.0) / n_u * (2.0 * np.pi / n_phi)
    return l, weight


def _view(mu: float) -> np.ndarray:
    return np.array([np.sqrt(1.0 - mu * mu), 0.0, mu])


def _mean_with_gaps(f: np.ndarray, ok: np.ndarray):
    """(π·mean, π·missing part) per channel: missing values taken as the mean of the
    others, their whole share counted as error. Only called with some value measured."""
    mean = f[..., ok].mean(axis=-1)
    return np.pi * mean, np.pi * mean * (1.0 - ok.mean())


def _weighted_with_gaps(f: np.ndarray, ok: np.ndarray, weight: np.ndarray):
    """(E, missing part) of E = Σ f · weight: unmeasured nodes taken at the measured
    nodes' weighted mean, their whole weight counted as error."""
    inside = weight > 0
    measured = ok & inside
    share = weight[measured].sum() / weight[inside].sum()
    E = (f[..., measured] * weight[measured]).sum(axis=-1) / share
    return E, E * (1.0 - share)


def _albedo_table(data: BrdfData) -> dict:
    channels = data.channels
    E = {c: [] for c in channels}
    err = {c: [] for c in channels}
    coverage, unmeasured = [], []
    every_other = data.table[:, ::2, ::2, ::2]
    for mu in MU:
        v = _view(mu)
        fine, coarse = _half_grid(*GRID_MERL, v), _half_grid(GRID_MERL[0] // 2, GRID_MERL[1] // 2, v)
        runs = []
        for (l, weight), table, stride in ((fine, data.table, 1), (fine, every_other, 2),
                                           (coarse, data.table, 1)):
            f = merl.lookup_linear(table, l, np.broadcast_to(v, l.shape), stride)
            ok = (f >= 0).all(axis=0)
            measured = ok & (weight > 0)
            runs.append(_weighted_with_gaps(f, ok, weight) if measured.any() else None)
            if stride == 1 and l is fine[0]:
                coverage.append(float(weight[measured].sum() / weight[weight > 0].sum()))
        if any(run is None for run in runs):     # nothing measured at this view direction
            unmeasured.append(float(mu))
            for c in channels:
                E[c].append(None)
                err[c].append(None)
            continue
        (full, gap), (sparse, _), (half, _) = runs
        for k, c in enumerate(channels):
            E[c].append(float(full[k]))
            err[c].append(float(abs(full[k] - sparse[k]) + abs(full[k] - half[k]) + gap[k]))
    theta_v = [round(float(np.degrees(np.arccos(m))), 2) for m in unmeasured]
    return {"mu": MU.tolist(), "E": E, "E_error": err, "coverage": coverage,
            "unmeasured": {"mu": unmeasured, "theta_v_deg": theta_v,
                           "note": (f"no cell is measured for the view directions at θ_v = "
                                    f"{', '.join(f'{t:g}°' for t in theta_v)}: E is null there"
                                    if unmeasured else "every view direction has measured cells"),
                           "coverage": "share of the light directions l (projected disk) "
                                       "measured at each μ; the rest counts fully into E_error"},
            "method": f"E(μ) = ∫ f (n·l) dl over the table, taken over the half vector h (dl = "
                      f"4 (v·h) dh), midpoint rule on a {GRID_MERL[0]} × {GRID_MERL[1]} grid in "
                      "(√(θ_h/90°), φ_h) — the table's own θ_h spacing, so a sharp peak is "
                      "resolved as finely as it was measured — f interpolated linearly between cell "
                      "centres; E_error = |all cells − every other cell| (interpolation: "
                      "linear interpolation's error is O(h²), so this is ~3× the error of the full "
                      "table) + |grid − half grid| (quadrature) + the share of unmeasured cells"}


def _reciprocity_table(data: BrdfData) -> dict:
    return {"max_relative_error": 0.0, "pairs": 0,
            "method": "exact by the format: a cell holds f at (θ_h, θ_d, φ_d), and swapping l "
                      "and v maps φ_d to φ_d + 180°, which a lookup folds onto the same cell"}


def _keys(theta, phi) -> np.ndarray:
    """Directions rounded to 1e-6° (azimuth mod 360°, 0 at the pole) as rows of a key
    array; ``+ 0.0`` makes −0 and +0 one key."""
    return np.round(np.column_stack([theta, np.mod(phi, 360.0) * (theta > 0)]), 6) + 0.0


def _row_ids(rows: np.ndarray) -> np.ndarray:
    """An integer per row of ``rows`` (m, k), equal for equal rows: column by column,
    each a 1-D np.unique of (id so far, value) folded into one int64 — k fast 1-D sorts
    instead of one slow sort of m structured rows."""
    ids = np.zeros(len(rows), np.int64)
    for col in rows.T:
        _, values = np.unique(col, return_inverse=True)
        _, ids = np.unique(ids * (values.max() + 1) + values, return_inverse=True)
    return ids.ravel()


def _swapped_pairs(data: BrdfData, isotropic: bool) -> tuple[np.ndarray, np.ndarray]:
    """(a, b) index arrays where sample b is sample a with l and v exchanged (a < b; of
    equal keys the last sample counts); with ``isotropic``, up to a rotation about n
    (keys (θ_i, θ_o, φ_o − φ_i)). One sort of keys and swapped keys together: O(n log n)."""
    (ti, pi), (to, po) = angles_deg(data.l), angles_deg(data.v)
    if isotropic:
        dphi = np.mod(po - pi, 360.0) * (ti > 0) * (to > 0)
        key = np.round(np.column_stack([ti, to, dphi]), 6) + 0.0
        swap = np.round(np.column_stack([to, ti, np.mod(-dphi, 360.0) * (dphi > 0)]), 6) + 0.0
    else:
        key = np.hstack([_keys(ti, pi), _keys(to, po)])
        swap = np.hstack([_keys(to, po), _keys(ti, pi)])
    n = len(key)
    inverse = _row_ids(np.vstack([key, swap]))
    last = np.full(inverse.max() + 1, -1)
    np.maximum.at(last, inverse[:n], np.arange(n))
    a = np.arange(n)
    b = last[inverse[n:]]
    keep = a < b                     # b = −1 (no swap in the data) is never > a
    return a[keep], b[keep]


def _reciprocity_samples(data: BrdfData) -> dict:
    (a, b), how = _swapped_pairs(data, False), "whose swap (l and v exchanged) is in the data"
    if not a.size:
        a, b = _swapped_pairs(data, True)
        how = ("whose swap is in the data up to a rotation about n (assuming the data "
               "isotropic)")
    if not a.size:
        return {"max_relative_error": None, "pairs": 0,
                "method": "no sample has its swap (l and v exchanged) in the data"}
    fa, fb = data.f[:, a], data.f[:, b]
    scale = np.maximum(fa, fb)
    rel = np.abs(fa - fb) / np.where(scale > 0, scale, 1.0)
    c, k = np.unravel_index(int(np.argmax(rel)), rel.shape)
    ti, pi = angles_deg(data.l[a[k]][None])
    to, po = angles_deg(data.v[a[k]][None])
    return {"max_relative_error": float(rel[c, k]), "pairs": int(a.size),
            "where": {"channel": data.channels[c], **{name: round(float(x[0]), 6) for name, x in (
                ("theta_i_deg", ti), ("phi_i_deg", pi), ("theta_o_deg", to), ("phi_o_deg", po))}},
            "method": f"|f(l, v) − f(v, l)| / max of the two over the samples {how}"}


class SummaryOverBudget(TooLarge):
    """The summary of an upload did not end within the request's time budget: 413 (the
    file is larger than this server summarises in BRDF_MAX_SECONDS), naming how far it got."""

    def __init__(self, done: int, total: int, seconds: float):
        super().__init__("file", f"summarising this file took longer than the request's time "
                                 f"budget (BRDF_MAX_SECONDS={seconds:g}): {done} of {total} view "
                                 "directions were checked; upload fewer samples or fewer "
                                 "distinct view directions", loc="body")


def _check_budget(done: int, total: int) -> None:
    """Cooperative cut between groups: raise once the request's budget is spent."""
    b = budget.current()
    if b is not None and b.elapsed() > b.seconds:
        raise SummaryOverBudget(done, total, b.seconds)


def _groups(fixed: np.ndarray, moving: np.ndarray) -> list:
    """[(μ of the fixed direction, sample indices)] of the fixed directions whose samples
    of the moving one cover enough of the projected hemisphere. One sort groups the
    samples (O(n log n)); only groups of ≥ MIN_GROUP samples are triangulated (a convex
    hull, O(m log m) for m samples), so all hulls together cost O(n log n)."""
    keys = _keys(*angles_deg(fixed))
    ids = _row_ids(keys)
    first, counts = np.unique(ids, return_index=True, return_counts=True)[1:]
    keys, inverse = keys[first], ids
    order = np.argsort(inverse.ravel(), kind="stable")     # each group's indices ascending
    ends = np.cumsum(counts)
    big = np.flatnonzero(counts >= MIN_GROUP)
    usable = []
    for done, g in enumerate(big):
        _check_budget(done, big.size)
        members = order[ends[g] - counts[g]:ends[g]]
        if _hull_area(moving[members, :2]) >= MIN_COVER * np.pi:
            usable.append((float(np.cos(np.deg2rad(keys[g, 0]))), members))
    return usable


def _albedo_samples(data: BrdfData) -> dict:
    fixed, moving, over = data.v, data.l, "l at fixed v"
    usable = _groups(fixed, moving)
    if not usable:   # E(μ) is also ∫ f (n·v) dv at fixed l, for a reciprocal BRDF
        fixed, moving, over = data.l, data.v, "v at fixed l (the same E for a reciprocal BRDF)"
        usable = _groups(fixed, moving)
    usable.sort(key=lambda item: item[0])
    if len(usable) > MAX_GROUPS:
        usable = [usable[k] for k in np.linspace(0, len(usable) - 1, MAX_GROUPS).round().astype(int)]
    E = {c: [] for c in data.channels}
    err = {c: [] for c in data.channels}
    fine, coarse = _disk(*GRID_SAMPLES), _disk(GRID_SAMPLES[0] // 2, GRID_SAMPLES[1] // 2)
    subset = ""
    for done, (_, members) in enumerate(usable):
        _check_budget(done, len(usable))
        if members.size > MAX_TRIANGULATED:
            members = np.sort(np.random.default_rng(0).choice(members, MAX_TRIANGULATED, replace=False))
            subset = (f"; a direction with more than {MAX_TRIANGULATED} samples is integrated "
                      "from a fixed-seed random subset of that many")
        xy, f = moving[members, :2], data.f[:, members].T
        linear, nearest = LinearNDInterpolator(xy, f), NearestNDInterpolator(xy, f)

        def integrate(grid, lin=True):
            near = nearest(grid[:, :2])
            if not lin:
                return np.pi * near.mean(axis=0)
            value = linear(grid[:, :2])
            inside = np.isfinite(value).all(axis=1)   # outside the convex hull: nearest
            return np.pi * np.where(inside[:, None], value, near).mean(axis=0)
        lin, near, half = integrate(fine), integrate(fine, False), integrate(coarse)
        for k, c in enumerate(data.channels):
            E[c].append(float(lin[k]))
            err[c].append(float(abs(lin[k] - near[k]) + abs(lin[k] - half[k])))
    return {"mu": [m for m, _ in usable], "E": E, "E_error": err,
            "method": f"integrated over {over}, for each fixed direction with ≥ {MIN_GROUP} "
                      f"samples spanning ≥ {MIN_COVER:.0%} of the projected hemisphere: E(μ) = ∫ f "
                      "(n·l) dl, f interpolated linearly over the projected directions (nearest "
                      "sample outside their hull), midpoint rule on a "
                      f"{GRID_SAMPLES[0]} × {GRID_SAMPLES[1]} (ρ², φ) grid; E_error = |linear − "
                      "nearest| (interpolation) + |grid − half grid| (quadrature)" + subset}


def _hull_area(xy: np.ndarray) -> float:
    try:
        return float(ConvexHull(xy).volume)   # a 2-D hull's "volume" is its area
    except (QhullError, ValueError):
        return 0.0


def _term(data: TermData) -> dict:
    out = {"axis": data.axis, "axis_range": [float(data.x.min()), float(data.x.max())],
           "range": {k: [float(x.min()), float(x.max())] for k, x in data.terms.items()}}
    order = np.argsort(data.x)
    x = data.x[order]
    if "D" in data.terms and x.size >= 3:
        t = np.deg2rad(x)
        integrand = 2.0 * np.pi * data.terms["D"][order] * np.cos(t) * np.sin(t)
        full = np.trapezoid(integrand, t)
        half = np.trapezoid(integrand[::2], t[::2])
        out["D_normalisation"] = {
            "value": float(full), "error": float(abs(full - half)), "expected": 1.0,
            "method": "2π ∫ D(θ) cos θ sin θ dθ over the given θ (an isotropic D; ∫ D (n·m) dm "
                      "= 1 for a normalised NDF), trapezoid rule; error = |all points − every "
                      "other point|" + ("" if x[0] <= 0 and x[-1] >= 90 else
                                         f"; only θ in [{x[0]:g}°, {x[-1]:g}°] is given")}
    if "E" in data.terms and x.size >= 3:
        integrand = 2.0 * data.terms["E"][order] * x
        full = np.trapezoid(integrand, x)
        half = np.trapezoid(integrand[::2], x[::2])
        out["E_avg"] = {"value": float(full), "error": float(abs(full - half)),
                        "method": "2 ∫ E(μ) μ dμ over the given μ, trapezoid rule; error = |all "
                                  "points − every other point|"}
    return out

