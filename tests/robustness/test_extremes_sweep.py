"""Numerical extremes, swept over every model the registry allows.

For every NDF × masking × G2 × Fresnel combination that :func:`app.model.make_spec`
accepts (the registries are enumerated, so a new model is swept as soon as it is
registered), a set of models: α ∈ ALPHAS (and α = 1 − 1e-9, where GTR's normalisation
has a removable singularity), anisotropic (1e-4, 1) where the combination allows it,
and every other parameter of the combination — NDF shape, Fresnel — one at a time at
its edges, just inside them, and at 1 ± 1e-9 when 1 is inside (γ = 1 for GTR, a
removable singularity), the others at their defaults (shape parameters at both ends of
α, Fresnel's at α = 1e-4, the sharpest lobe).

Each model is evaluated at every pair (l, v) of DIRECTIONS (θ ∈ THETAS × φ ∈ PHIS, so
l = v, both grazing, one grazing, normal incidence) and at l = −v, and must give:

* f, D, G1, G2, F, Λ with no NaN, finite — except the documented divergences: Λ = +inf
  exactly at μ = 0; f = +inf only where both directions graze; D = +inf only for a half
  vector on the horizon (Student-t with γ < 2, whose tail is heavier than GGX's:
  D ~ tan^{4−2γ} θ_m there);
* 0 ≤ G1_i, G1_o, G2 ≤ 1; 0 ≤ F ≤ 1; f, D ≥ 0;
* continuity through the removable singularities: D and μΛ at a parameter 1 ± 1e-9
  equal to their value at 1 (relative 1e-6), and D at θ_m = 90° − 1e-9° equal to D at
  90° (D is continuous at the horizon for every NDF here);
* E(μ) finite, ≥ −E_error, and — where Λ is the exact Smith Λ — ≤ 1 + E_error, at
  μ ∈ {0, 0.5} for α ∈ {1e-3, 1}, with F = 1 and kd = 0 (the single-scattering albedo
  cannot exceed 1; F ≤ 1 only lowers it). An approximate Λ may break the bound: Blinn-
  Phong with Walter's Beckmann Λ gives E(0) = 1.77 at α = 1 (height-correlated).

High-precision references (mpmath, 50 digits) for GGX and Beckmann at the worst points
are in :mod:`tests.robustness.test_extremes_mpmath`.

Floating-point state: overflow, divide and invalid raise, warnings are errors; underflow
(exp(−tan²θ/α²) → 0 for Beckmann at small α) is the correct value and is ignored.
"""
from __future__ import annotations

import itertools
import math

import numpy as np
import pytest

from app.integrate.albedo import albedo
from app.errors import ParameterError
from app.model import OPTIONS, choice_params, make_spec
from tests.strict import strict

ALPHAS = [1e-4, 1e-3, 0.01, 0.5, 1.0 - 1e-9, 1.0]
THETAS = [0.0, 1e-7, 45.0, 89.99, 89.9999, 90.0]
PHIS = [0.0, 37.0, 180.0]
#: relative step "just inside" an edge, and around 1
EPS = 1e-9
#: relative agreement asked across a removable singularity (the step is 1e-9: a
#: formula that is continuous there moves by ~1e-9 relative; 1e-6 leaves room for the
#: conditioning of the formula, and a sign or branch error moves by O(1))
CONTINUITY_RTOL = 1e-6
ALBEDO_ALPHAS = [1e-3, 1.0]
ALBEDO_MU = np.array([0.0, 0.5])
ALBEDO_ORDER = 24
#: the options swept against each other. Others (multiple scattering) stay at their
#: default: a compensated model builds tables over α for each model, which is its
#: owner's to test, and would make this sweep hours long.
SWEPT = ("ndf", "masking", "g2", "fresnel")
#: filled while the tests run; the summary (conftest.py) prints the size of the sweep
SIZE = {"combinations": 0, "models": 0, "points": 0}


def direction(theta_deg, phi_deg):
    """ω from degrees, written here (not app.physics.vectors): μ is exactly 0 at 90°
    and exactly 1 at 0°, so 'grazing' means grazing."""
    t, p = np.deg2rad(theta_deg), np.deg2rad(phi_deg)
    st = np.where(theta_deg == 90.0, 1.0, np.sin(t))
    ct = np.where(theta_deg == 90.0, 0.0, np.cos(t))
    return np.stack([st * np.cos(p), st * np.sin(p), ct], axis=-1)


DIRECTIONS = direction(*map(np.ravel, np.meshgrid(THETAS, PHIS, indexing="ij")))
PAIR_L = np.concatenate([np.repeat(DIRECTIONS, len(DIRECTIONS), axis=0), -DIRECTIONS])
PAIR_V = np.concatenate([np.tile(DIRECTIONS, (len(DIRECTIONS), 1)), DIRECTIONS])


# --------------------------------------------------------------------- the models

def combinations():
    """Every (ndf, masking, g2, fresnel) that make_spec accepts with default parameters;
    any other option at its default."""
    for combo in itertools.product(*[list(OPTIONS[o][1]) for o in SWEPT]):
        values = dict(zip(SWEPT, combo))
        try:
            make_spec(**values)
        except ParameterError:
            continue                 # not a model: enumeration, not a skipped test
        yield values


COMBINATIONS = list(combinations())


def edges(p) -> list[float]:
    """A parameter's edges and the points just inside them, and 1 ± EPS if inside."""
    step_lo, step_hi = EPS * max(1.0, abs(p.lo)), EPS * max(1.0, abs(p.hi))
    out = [p.lo + step_lo, p.hi - step_hi, p.hi]
    if not p.lo_open:
        out.append(p.lo)
    out += [x for x in (1.0 - EPS, 1.0, 1.0 + EPS) if p.contains(x)]
    return sorted(set(out))


def models(combo: dict):
    """(label, make_spec values, continuity group) for one combination; the models of a
    group differ only in one parameter, at 1 and 1 ± EPS."""
    for a in ALPHAS:
        yield f"alpha={a!r}", {**combo, "alpha": a}, ("alpha",) if abs(a - 1) <= EPS else None
    yield "alpha=1e-4,alpha_y=1", {**combo, "alpha": 1e-4, "alpha_y": 1.0}, None
    # shape parameters change D and Λ: at both ends of α; Fresnel's only change F, whose
    # range does not depend on α: at the sharpest lobe (largest D, hence f)
    params = [(p, (1e-4, 1.0)) for p in choice_params("ndf", combo["ndf"])]
    params += [(p, (1e-4,)) for p in choice_params("fresnel", combo["fresnel"])]
    for p, alphas in params:
        for x in edges(p):
            for a in alphas:
                group = (p.name, a) if abs(x - 1) <= EPS else None
                yield f"{p.name}={x!r},alpha={a:g}", {**combo, "alpha": a, p.name: x}, group


def _spec(values):
    try:
        return make_spec(**values)
    except ParameterError as e:
        # an anisotropic α with an isotropic-only NDF or G2: not a model
        assert e.param in ("alpha_y", "g2", "ndf"), (values, e.message)
        return None


def _id(combo):
    return "-".join(combo.values())


# --------------------------------------------------------------------- the checks

def check_values(label, brdf, out, Lambda, mu):
    """Finite, in range; the documented divergences only where documented."""
    both_graze = (PAIR_L[:, 2] == 0.0) & (PAIR_V[:, 2] == 0.0)
    h_on_horizon = (PAIR_L[:, 2] + PAIR_V[:, 2] == 0.0)
    for q in ("G1_i", "G1_o", "G2", "F"):
        assert np.all(np.isfinite(out[q])), (label, q, PAIR_L[~np.isfinite(out[q])][:3])
    assert not np.any(np.isnan(out["D"])), label
    assert np.all(np.isfinite(out["D"][~h_on_horizon])), (label, "D not finite off the horizon")
    assert not np.any(np.isnan(out["f"])), label
    assert np.all(np.isfinite(out["f"][~both_graze])), \
        (label, "f not finite where not both grazing", PAIR_L[~both_graze & ~np.isfinite(out["f"])][:3])
    assert np.all(out["f"] >= 0.0) and np.all(out["D"] >= 0.0), label
    for q in ("G1_i", "G1_o", "G2", "F"):
        assert np.all((out[q] >= 0.0) & (out[q] <= 1.0)), (label, q, out[q].min(), out[q].max())
    assert not np.any(np.isnan(Lambda)), label
    assert np.all(Lambda[mu == 0.0] == np.inf), (label, "Λ at μ = 0", Lambda[mu == 0.0])
    assert np.all(np.isfinite(Lambda[mu > 0.0])) and np.all(Lambda[mu > 0.0] >= 0.0), label


def check_horizon(label, brdf):
    """D continuous at the horizon: D(90° − 1e-9°) → D(90°) to 1e-12 of the peak D(n)
    (Blinn-Phong's cos^p θ is 4e-65 there and 0 on it: continuous); where D(90°) is the
    divergence +inf, D just above it is finite and larger than at 89°.

    For α → 1 Blinn-Phong's exponent α_p = 2/α² − 2 → 0 and cos^{α_p} θ, continuous for
    every α_p > 0, falls from 1 to 0 within less than 1e-9° of the horizon: no fixed step
    resolves it, so the check is made for α ≤ 0.5."""
    phis = np.array(PHIS)
    with strict():
        d90 = brdf.ndf.D(direction(np.full(len(PHIS), 90.0), phis))
        d_near = brdf.ndf.D(direction(np.full(len(PHIS), 90.0 - 1e-9), phis))
        d89 = brdf.ndf.D(direction(np.full(len(PHIS), 89.0), phis))
        peak = brdf.ndf.D(np.array([0.0, 0.0, 1.0]))
    finite = np.isfinite(d90)
    np.testing.assert_allclose(d_near[finite], d90[finite], rtol=CONTINUITY_RTOL,
                               atol=1e-12 * peak, err_msg=label)
    assert np.all(np.isfinite(d_near[~finite]) & (d_near[~finite] > d89[~finite])), label


def evaluate(spec):
    brdf = spec.brdf()
    with strict():
        out = brdf.evaluate(PAIR_L, PAIR_V, ("f", "D", "G1_i", "G1_o", "G2", "F"))
        ml = brdf.masking.mu_Lambda(brdf.ndf, DIRECTIONS)
    mu = DIRECTIONS[:, 2]
    Lambda = np.full_like(mu, np.inf)
    np.divide(ml, mu, out=Lambda, where=mu > 0)
    return brdf, out, ml, Lambda, mu


@pytest.mark.parametrize("combo", COMBINATIONS, ids=_id)
def test_sweep(combo):
    SIZE["combinations"] += 1
    groups: dict[tuple, list] = {}
    for label, values, group in models(combo):
        spec = _spec(values)
        if spec is None:
            continue
        brdf, out, ml, Lambda, mu = evaluate(spec)
        SIZE["models"] += 1
        SIZE["points"] += len(PAIR_L)
        check_values(f"{_id(combo)} {label}", brdf, out, Lambda, mu)
        if values["alpha"] <= 0.5:
            check_horizon(label, brdf)
        if group is not None:
            groups.setdefault(group, []).append((label, out["D"], ml))
    # continuity in a parameter through 1 (GTR's γ = 1 and α = 1 are removable
    # singularities of its normalisation), for half vectors above the horizon: on it a
    # family like Blinn-Phong's cos^{α_p} θ_m truly jumps at α_p = 0 (α = 1)
    above = PAIR_L[:, 2] + PAIR_V[:, 2] > 0.0
    for group, members in groups.items():
        _, ref_D, ref_ml = members[0]
        for label, D, ml in members[1:]:
            np.testing.assert_allclose(D[above], ref_D[above], rtol=CONTINUITY_RTOL, atol=1e-300,
                                       err_msg=f"{_id(combo)}: D jumps at {label}")
            np.testing.assert_allclose(ml, ref_ml, rtol=CONTINUITY_RTOL, atol=1e-300,
                                       err_msg=f"{_id(combo)}: μΛ jumps at {label}")


#: F ≤ 1 can only lower E: the bound is checked with F = 1 (fresnel=none)
ALBEDO_COMBINATIONS = [c for c in COMBINATIONS if c["fresnel"] == "none"]


def _exact_smith(combo) -> bool:
    """E ≤ 1 is a theorem for the exact Smith Λ; an approximate Λ may break it (Blinn-
    Phong with Walter's Beckmann Λ reflects E(0) = 1.40 at α = 1: the model's truth, which
    the albedo chart flags as not energy-conserving)."""
    from app.physics.ndf import NDFS
    return combo["masking"] == "smith_numeric" or (
        combo["masking"] == "smith" and NDFS[combo["ndf"]].smith_exact)


@pytest.mark.parametrize("combo", ALBEDO_COMBINATIONS, ids=_id)
def test_albedo_at_most_one(combo):
    """E(μ) ≤ 1 + E_error for the exact Smith Λ (finite and ≥ −E_error for every
    masking): with kd = 0 and F = 1 a single-scattering BRDF reflects at most what
    arrives (Kulla & Conty 2017; docs/identities.md §7); at grazing (μ = 0, where masking
    matters most) and at μ = 0.5."""
    for a in ALBEDO_ALPHAS:
        brdf = make_spec(**combo, alpha=a).brdf()
        with strict():
            res = albedo(brdf, ALBEDO_MU, order=ALBEDO_ORDER)
        assert np.all(np.isfinite(res.E)) and np.all(np.isfinite(res.E_error)), (combo, a)
        assert np.all(res.E >= -res.E_error), (combo, a, res.E, res.E_error)
        if _exact_smith(combo):
            assert np.all(res.E <= 1.0 + res.E_error), (combo, a, res.E, res.E_error)


def test_every_option_is_swept():
    """Each registered choice appears in at least one combination (a choice that
    make_spec never accepts would escape the sweep silently)."""
    for option in SWEPT:
        seen = {c[option] for c in COMBINATIONS}
        assert seen == set(OPTIONS[option][1]), (option, set(OPTIONS[option][1]) - seen)
    assert math.prod(len(OPTIONS[o][1]) for o in SWEPT) >= len(COMBINATIONS) > 0
