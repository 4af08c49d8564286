"""Kulla-Conty's furnace for every NDF over its shape range at α ∈ {0.05, 0.37, 1}: the
stated ``compensation_error`` is at most 1e-4 and the furnace ∫ (f + f_ms) cos dl at F = 1,
integrated independently, is 1 within it (issue 37).

The reference is independent of the table's quadrature (albedo.py, over l in the
(μ_l, φ) of the view): E_single by slope-space quadrature over the visible normals m,
l = 2(v·m)m − v (slope_quadrature.py, written from D alone) where its bound is tight, the
albedo.py quadrature at tol 1e-9 where it is not (heavy tails; agreeing with the slope-space
value within both bounds), and the albedo of f_ms by Gauss-Legendre over μ_l of the lobe
function itself; at μ between the slice's nodes."""
import numpy as np
import pytest

from app.integrate import slope_quadrature as sq
from app.integrate.albedo import albedo
from app.model import make_spec

GOAL = 1e-4
REFERENCE_TOL = 1e-6
#: The slope-space quadrature stops doubling its order below this error (its default,
#: 1e-11, took a level 4× the last one for nothing here: its error enters the check as
#: it is, next to a stated error ≥ 1e-5)
SLOPE_TARGET = 1e-7
MU = np.array([0.003, 0.041, 0.23, 0.61, 0.93])
#: Gauss-Legendre on μ_l ∈ [0, 1] for f_ms's albedo, computed once (numpy's leggauss(400)
#: solves a 400×400 eigenproblem: ~0.3 s a call, a quarter of this file's time)
_x, _w = np.polynomial.legendre.leggauss(400)
MS_MU_L, MS_WEIGHT = 0.5 * (_x + 1.0), 0.5 * _w
AGREEMENT = 3e-5

# Each NDF's declared shape range, both ends and between (app/physics/ndf/*.py):
# GTR γ ∈ [0.5, 10], exp_power p ∈ [0.25, 4], Student-t γ ∈ (1.5, 1000] from the first
# double above 1.5 (its E falls from 1 at μ ~ e^{−1/(2γ−3)}, for γ < 1.5007 below the
# smallest double, where the slice takes E's grazing asymptote: docs/tables.md §5).
STUDENT_T_LOWEST = float(np.nextafter(1.5, 2.0))
SHAPES = [("ggx", {}), ("beckmann", {}), ("blinn_phong", {}),
          ("gtr", {"gamma": 0.5}), ("gtr", {"gamma": 1.0}), ("gtr", {"gamma": 1.05}),
          ("gtr", {"gamma": 1.5}), ("gtr", {"gamma": 1.9}), ("gtr", {"gamma": 10.0}),
          ("exp_power", {"p": 0.25}), ("exp_power", {"p": 0.3}), ("exp_power", {"p": 1.763}),
          ("exp_power", {"p": 3.0}), ("exp_power", {"p": 4.0}),
          ("student_t", {"gamma": STUDENT_T_LOWEST}), ("student_t", {"gamma": 1.500001}),
          ("student_t", {"gamma": 1.501}), ("student_t", {"gamma": 1.51}), ("student_t", {"gamma": 1.55}),
          ("student_t", {"gamma": 1.6}), ("student_t", {"gamma": 1.8}),
          ("student_t", {"gamma": 3.0}), ("student_t", {"gamma": 1000.0})]


def E_single_slope_space(brdf, mu_v: float) -> tuple[float, float]:
    """∫ f(l, v) μ_l dl over the visible normals m (slope_quadrature.rule/l_area/refine)."""
    ndf = brdf.ndf
    v = np.array([np.sqrt(1.0 - mu_v * mu_v), 0.0, mu_v])
    k = sq.tail_k(ndf)

    def level(n):
        rule = sq.rule(ndf.alpha_x, ndf.alpha_y, v, n, visible=True, k=k)
        l, area = sq.l_area(ndf.alpha_x, ndf.alpha_y, v, rule)
        up = l[:, 2] > 0
        terms = np.zeros(rule.size)
        terms[up] = brdf.f(l[up], np.broadcast_to(v, l[up].shape)) * l[up, 2] * area[up] * rule.weight[up]
        return float(np.sum(terms)), float(np.sum(np.abs(terms))), rule.size, 0.0

    res = sq.refine(level, target=SLOPE_TARGET)
    return res.value, res.error


def E_single_reference(brdf, mu_v: float) -> tuple[float, float]:
    """The slope-space value where its own bound is ≤ REFERENCE_TOL; where it is looser
    (heavy tails: its order is capped), the albedo.py quadrature at tol 1e-9, its
    uncertainty the larger of its bound and its distance from the slope-space value (at
    most AGREEMENT, under a third of GOAL, so the test can fail by the stated error)."""
    E, err = E_single_slope_space(brdf, mu_v)
    if err <= REFERENCE_TOL:
        return E, err
    res = albedo(brdf, np.array([mu_v]), tol=1e-9)
    # consistent with the slope-space value within both bounds: its own bound; otherwise
    # (up to 2.2e-5 measured, 1.5× the slope-space bound: Beckmann α = 0.37, GTR γ = 1.9)
    # the disagreement is the reference's uncertainty
    diff = abs(float(res.E[0]) - E)
    uncertainty = float(res.E_error[0]) if diff <= err + res.E_error[0] else diff
    assert uncertainty <= AGREEMENT
    return float(res.E[0]), uncertainty


def ms_albedo(brdf, mu_v):
    """2π ∫₀¹ f_ms(μ_l, μ_v) μ_l dμ_l (f_ms depends on μ_l alone, not on φ)."""
    f = brdf.multiscatter(MS_MU_L[:, None], np.asarray(mu_v)[None, :])
    return 2.0 * np.pi * np.sum(f * (MS_MU_L * MS_WEIGHT)[:, None], axis=0)


@pytest.mark.parametrize("alpha", [0.05, 0.37, 1.0])
@pytest.mark.parametrize("ndf,shape", SHAPES, ids=[f"{n}{s}" for n, s in SHAPES])
def test_furnace_within_stated_error(ndf, shape, alpha):
    masking = "smith_numeric" if ndf == "blinn_phong" else "smith"
    brdf = make_spec(ndf=ndf, alpha=alpha, fresnel="none", masking=masking,
                     multiscatter="kulla_conty", **shape).brdf()
    stated = brdf.multiscatter.error
    assert stated <= GOAL
    single = brdf.single()
    for mu, E_ms in zip(MU, ms_albedo(brdf, MU)):
        E, err = E_single_reference(single, float(mu))
        assert abs(E + E_ms - 1.0) <= stated + err + 1e-9, (mu, E + E_ms - 1.0, stated, err)



@pytest.mark.parametrize("gamma", [1.501, 1.51])
def test_grazing_asymptote_against_quadrature(gamma):
    """Below MU_TAIL the slice's nodes come from E's grazing asymptote 1 − A μ^{2γ−3}
    (docs/tables.md §5), not from the quadrature; down to 1e-145, where the albedo
    quadrature still converges, it answers within its stated error of it (at γ = 1.51
    E(1e-145) is 0.9988: the asymptote carries E's whole fall from 1 below 1e-100)."""
    from app.integrate.tables.alpha_slice import MU_TAIL
    brdf = make_spec(ndf="student_t", alpha=0.37, fresnel="none", masking="smith",
                     multiscatter="kulla_conty", gamma=gamma).brdf()
    table = brdf.multiscatter.lobes[0].table
    assert table.error <= GOAL
    mu = np.array([0.9 * MU_TAIL, 1e-117, 1e-131, 1e-145])
    res = albedo(brdf.single(), mu, tol=1e-9)
    assert np.all(res.E_error <= 1e-8)
    assert np.all(np.abs(table.E(mu, 0.37) - res.E) <= table.error + res.E_error)
