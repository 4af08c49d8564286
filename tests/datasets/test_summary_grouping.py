"""The samples summary's grouping and reciprocity pairs against a brute-force second
implementation (a dict of every key, a scan of every group): the same pairs, the same
view directions, the same E on small files; a cooperative cut at the request's budget.

The brute force is the definition written plainly: samples share a view direction when
their (θ, φ) agree to 1e-6° (φ ignored at the pole); a direction is integrated when it
has ≥ MIN_GROUP samples whose projected light directions' convex hull covers
≥ MIN_COVER of the unit disk; at most MAX_GROUPS of them, evenly spread in μ.
"""
from __future__ import annotations

import io

import numpy as np
import pytest
from scipy.spatial import ConvexHull

from app.datasets import formats, summary
from app.integrate import budget
from tests.budget import settings_for_tests


def _direction(theta_deg, phi_deg):
    t, p = np.radians(theta_deg), np.radians(phi_deg)
    return np.stack([np.sin(t) * np.cos(p), np.sin(t) * np.sin(p), np.cos(t)], axis=-1)


def _csv(rows) -> bytes:
    out = io.StringIO()
    np.savetxt(out, rows, delimiter=",", fmt="%.17g",
               header="theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f", comments="")
    return out.getvalue().encode()


def _file(seed: int, views: int, per_view: int, swaps: int) -> np.ndarray:
    """Rows (θ_i, φ_i, θ_o, φ_o, f): ``views`` view directions with ``per_view`` random
    light directions each (some views on the pole, some with few samples), plus
    ``swaps`` rows that are earlier rows with l and v exchanged (f perturbed)."""
    rng = np.random.default_rng(seed)
    rows = []
    for k in range(views):
        to = 0.0 if k == 0 else float(rng.choice([10.0, 25.5, 40.0, 71.25, 85.0]) + 0.1 * k)
        po = float(rng.uniform(0, 360)) if k % 3 else 0.0
        n = per_view if k % 4 else 12             # every fourth too small to integrate
        ti = np.degrees(np.arccos(np.sqrt(rng.uniform(0, 1, n))))
        pi = rng.uniform(0, 360, n)
        if k % 5 == 2:
            pi = rng.uniform(0, 90, n)            # a quarter of the disk: too little cover
        f = rng.uniform(0.05, 3.0, n)
        rows += [(a, b, to, po, c) for a, b, c in zip(ti, pi, f)]
    rows = np.array(rows)
    pick = rng.choice(len(rows), swaps, replace=False)
    swapped = rows[pick][:, [2, 3, 0, 1, 4]]
    swapped[:, 4] *= rng.uniform(0.8, 1.2, swaps)
    return np.vstack([rows, swapped])


def _brute_groups(l, v):
    key = lambda w: (round(float(np.degrees(np.arccos(np.clip(w[2], -1, 1)))), 6),
                     round(float(np.mod(np.degrees(np.arctan2(w[1], w[0])), 360.0))
                           * (np.degrees(np.arccos(np.clip(w[2], -1, 1))) > 0), 6))
    groups = {}
    for n, w in enumerate(v):
        k = key(w)
        groups.setdefault((k[0] + 0.0, k[1] + 0.0), []).append(n)
    usable = []
    for (theta, _), members in groups.items():
        if len(members) < summary.MIN_GROUP:
            continue
        try:
            area = ConvexHull(l[members, :2]).volume
        except Exception:
            area = 0.0
        if area >= summary.MIN_COVER * np.pi:
            usable.append((float(np.cos(np.radians(theta))), members))
    usable.sort(key=lambda item: item[0])
    if len(usable) > summary.MAX_GROUPS:
        usable = [usable[k] for k in np.linspace(0, len(usable) - 1, summary.MAX_GROUPS).round().astype(int)]
    return usable


def _brute_pairs(rows):
    """Pairs (a, b), a < b, with row b = row a's l and v exchanged (keys to 1e-6°)."""
    def k(t, p):
        return (round(t, 6) + 0.0, round(p % 360.0 * (t > 0), 6) + 0.0)
    last = {}
    for n, r in enumerate(rows):
        last[k(r[0], r[1]) + k(r[2], r[3])] = n
    pairs = []
    for n, r in enumerate(rows):
        b = last.get(k(r[2], r[3]) + k(r[0], r[1]))
        if b is not None and n < b:
            pairs.append((n, b))
    return pairs


@pytest.mark.parametrize("seed, views, per_view, swaps", [(1, 9, 40, 30), (2, 30, 36, 5), (3, 4, 200, 0)])
def test_grouping_and_pairs_match_the_brute_force(seed, views, per_view, swaps):
    rows = _file(seed, views, per_view, swaps)
    data = formats.load(_csv(rows))
    info = summary.summarize(data)
    expected = _brute_groups(data.l, data.v)
    assert info["albedo"]["mu"] == [m for m, _ in expected]
    assert len(expected) >= 2
    pairs = _brute_pairs(_angles(data))
    if swaps:
        assert info["reciprocity"]["pairs"] == len(pairs) > 0
        a, b = (np.array(x) for x in zip(*pairs))
        rel = np.abs(data.f[0, a] - data.f[0, b]) / np.maximum(data.f[0, a], data.f[0, b])
        assert info["reciprocity"]["max_relative_error"] == pytest.approx(rel.max(), rel=1e-12)
    for (mu, members), E in zip(expected, info["albedo"]["E"]["f"]):
        # E at one direction is π × the mean over the disk of f interpolated from exactly
        # these samples: a permutation or subset error would change it
        assert E == pytest.approx(_E_linear(data.l[members, :2], data.f[0, members]), rel=1e-12)


def _angles(data):
    out = []
    for l, v in zip(data.l, data.v):
        ti = float(np.degrees(np.arccos(np.clip(l[2], -1, 1))))
        to = float(np.degrees(np.arccos(np.clip(v[2], -1, 1))))
        out.append((ti, float(np.degrees(np.arctan2(l[1], l[0]))), to, float(np.degrees(np.arctan2(v[1], v[0])))))
    return out


def _E_linear(xy, f):
    from scipy.interpolate import LinearNDInterpolator, NearestNDInterpolator
    n_s, n_phi = summary.GRID_SAMPLES
    s = (np.arange(n_s) + 0.5) / n_s
    phi = (np.arange(n_phi) + 0.5) * 2 * np.pi / n_phi
    grid = np.stack([np.outer(np.sqrt(s), np.cos(phi)).ravel(), np.outer(np.sqrt(s), np.sin(phi)).ravel()], -1)
    lin = LinearNDInterpolator(xy, f)(grid)
    near = NearestNDInterpolator(xy, f)(grid)
    return np.pi * np.where(np.isfinite(lin), lin, near).mean()


def test_a_summary_past_the_budget_is_cut_with_a_413_naming_it():
    rows = _file(4, 12, 40, 0)
    data = formats.load(_csv(rows))
    with budget.limit(0.0):
        with pytest.raises(summary.SummaryOverBudget) as err:
            summary.summarize(data)
    assert err.value.status == 413 and "BRDF_MAX_SECONDS" in err.value.message


def test_the_api_answers_the_cut_as_413():
    import warnings
    with warnings.catch_warnings():
        warnings.simplefilter("ignore", DeprecationWarning)
        from fastapi.testclient import TestClient
    from app.main import create_app
    client = TestClient(create_app(settings_for_tests(max_seconds=1e-6)))
    res = client.post("/api/v1/datasets", content=_csv(_file(5, 12, 40, 0)))
    assert res.status_code in (413, 503), res.text
    if res.status_code == 413:
        assert "BRDF_MAX_SECONDS" in res.json()["detail"][0]["msg"]
