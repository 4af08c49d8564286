"""The slope-space quadrature's pieces against independent computations."""
import mpmath as mp
import pytest

from app.integrate import slope_quadrature as sq
from app.physics.vectors import direction_deg


def test_l_area_element_against_mpmath():
    """Row 4's area element |∂l/∂r̃ × ∂l/∂ψ| against mpmath's numerical derivatives of
    the map (r̃, ψ) → l = 2(v·m)m − v written out independently."""
    v = direction_deg(60.0, 30.0)
    ax, ay = 0.3, 0.05
    rule = sq.rule(ax, ay, v, 4, visible=True)
    _, area = sq.l_area(ax, ay, v, rule)
    V = [mp.mpf(float(x)) for x in v]

    def l_of(r, p):
        X, Y = ax * r * mp.cos(p), ay * r * mp.sin(p)
        n = mp.sqrt(1 + X * X + Y * Y)
        m = [X / n, Y / n, 1 / n]
        vm = sum(V[i] * m[i] for i in range(3))
        return [2 * vm * m[i] - V[i] for i in range(3)]

    with mp.workdps(30):
        for k in range(0, rule.size, 7):
            b, p = mp.mpf(float(rule.r[k])), mp.mpf(float(rule.psi[k]))
            db = [mp.diff(lambda x: l_of(x, p)[i], b) for i in range(3)]
            dp = [mp.diff(lambda x: l_of(b, x)[i], p) for i in range(3)]
            cross = [db[1] * dp[2] - db[2] * dp[1], db[2] * dp[0] - db[0] * dp[2],
                     db[0] * dp[1] - db[1] * dp[0]]
            assert area[k] == pytest.approx(float(mp.sqrt(sum(c * c for c in cross))), rel=1e-10)
