"""Least squares with a time budget, and standard errors from the Jacobian.

scipy's trust-region reflective least squares (``least_squares(method="trf")``) within
the registry's bounds, log-scaled parameters in their logarithm. The residual function
counts evaluations and keeps the best point seen, so a fit stopped by its time budget
answers with that point and says so.

Standard errors: cov = s² (JᵀJ)⁻¹ with s² = Σr²/(n − p), J = ∂r/∂θ by central
differences at the optimum (the Gauss-Newton approximation of the inverse Hessian;
Press et al., Numerical Recipes, 15.5). They are honest when the residuals are
independent with equal variance in the chosen measure — e.g. multiplicative noise and
the log measure — and describe nothing for a parameter stopped at a bound.
"""
from __future__ import annotations

import time

import numpy as np
from scipy.optimize import least_squares

from .problem import Problem

#: relative step of the central differences of the final Jacobian (in the internal,
#: log or linear, coordinate): ~ε^(1/3) of float64, the step that balances truncation
#: and rounding in a central difference
JACOBIAN_STEP = 6e-6
#: condition number of JᵀJ above which parameters are reported as not identifiable
MAX_CONDITION = 1e12
#: evaluations one fit may take at most, whatever its time budget
MAX_EVALUATIONS = 2000


class _OutOfTime(Exception):
    pass


def _coordinates(problem: Problem):
    """(to_user, to_internal, lo, hi): log for parameters the registry marks log-scaled."""
    log = np.array([p.scale == "log" and p.lo > 0 for p in problem.free])
    lo = np.array([np.log(p.lo) if g else p.lo for p, g in zip(problem.free, log)])
    hi = np.array([np.log(p.hi) if g else p.hi for p, g in zip(problem.free, log)])
    def to_user(y):
        x = np.array(y, dtype=float)
        x[log] = np.exp(x[log])
        return x

    def to_internal(x):
        # only the log-scaled parameters through log: the others may be 0 or negative
        # (k_d = 0), whose log np.where would have computed and thrown away (-inf, a warning)
        y = np.array(x, dtype=float)
        y[log] = np.log(y[log])
        return y

    return to_user, to_internal, lo, hi


def solve(problem: Problem, seconds: float) -> dict:
    """The best parameters within ``seconds`` and what is known of them."""
    start_time = time.perf_counter()
    to_user, to_internal, lo, hi = _coordinates(problem)
    best = {"cost": np.inf, "y": np.clip(to_internal(problem.start), lo, hi)}
    count = [0]

    def residual(y):
        if time.perf_counter() - start_time > seconds:
            raise _OutOfTime
        count[0] += 1
        r = problem.residual(to_user(y))
        cost = 0.5 * float(r @ r)
        if cost < best["cost"]:
            best.update(cost=cost, y=np.array(y))
        return r

    try:
        result = least_squares(residual, best["y"], bounds=(lo, hi), method="trf", x_scale=1.0,
                               xtol=1e-10, ftol=1e-10, gtol=1e-10, max_nfev=MAX_EVALUATIONS)
        y, converged, message = result.x, bool(result.status > 0), result.message
    except _OutOfTime:
        y, converged = best["y"], False
        message = f"stopped by its time budget ({seconds:.3g} s): the best point reached"
    x = to_user(y)
    r = problem.residual(x)
    J, extra = _jacobian(problem, y, to_user, lo, hi)
    return {"x": x, "stderr": _stderr(r, J), "r": r, "evaluations": count[0] + 1 + extra,
            "seconds": time.perf_counter() - start_time, "converged": converged, "message": message,
            "at_bound": [p.name for p, yi, a, b in zip(problem.free, y, lo, hi)
                         if np.isclose(yi, a, rtol=0, atol=1e-9) or np.isclose(yi, b, rtol=0, atol=1e-9)]}


def _jacobian(problem: Problem, y: np.ndarray, to_user, lo, hi):
    """∂r/∂x (user units) by central differences in the internal coordinate, one-sided
    at a bound; and the evaluations it took."""
    columns = []
    for k in range(y.size):
        h = JACOBIAN_STEP * max(1.0, abs(y[k]))
        up, down = y.copy(), y.copy()
        up[k], down[k] = min(y[k] + h, hi[k]), max(y[k] - h, lo[k])
        xu, xd = to_user(up), to_user(down)
        columns.append((problem.residual(xu) - problem.residual(xd)) / (xu[k] - xd[k]))
    return np.stack(columns, axis=1), 2 * y.size


def _stderr(r: np.ndarray, J: np.ndarray) -> np.ndarray | None:
    n, p = J.shape
    if n <= p:
        return None
    JtJ = J.T @ J
    if not np.isfinite(JtJ).all() or np.linalg.cond(JtJ) > MAX_CONDITION:
        return None
    s2 = float(r @ r) / (n - p)
    return np.sqrt(np.maximum(np.diag(np.linalg.inv(JtJ)) * s2, 0.0))
