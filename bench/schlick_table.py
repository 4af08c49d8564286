"""Schlick-basis table E_S(μ, α) (F = (1 − cos θ_d)^p): which representation a bicubic
table of it should hold, measured. E of a generalised Schlick F is F₀ E₁ + (F₉₀ − F₀) E_S,
so E_S's table error is what ``method=table`` and ``method=auto`` see for the default
model (GGX + Schlick).

Candidates (r = √α uniform on [0.01, 1], n nodes; m = (1 − μ)^p; μ axes: x = √μ; y the
F = 1 table's graded Smith axis; t = 0.3 y + 0.7 √μ, inverted numerically):

* A_ratio_x      ρ = E_S/E₁ on (r, x), E_S = ρ̂ Ê₁ (the representation before)
* B_delta_y      Δ = E_S − E₁ m on (r, y), E_S = Δ̂ + Ê₁ m
* B_delta_y/α    Δ/α on (r, y)
* B_delta_y/αL   Δ/w, w = α (1 + ln(1/α)), on (r, y) (Δ(μ = 0) ≈ −pα(ln(1/α) − 1.4), GGX)
* C_q_y          q = E_S/E₁ − m on (r, y), E_S = (q̂ + m) Ê₁
* D_ratio_t      ρ on (r, t);  D_direct_t: E_S itself on (r, t)
* E_direct_y     E_S itself on (r, y)
* F_delta_x      Δ on (r, x)
* G_…_r1         …, the first r cell split at its midpoint (one more row of nodes)
* K_…_r1_y111    …, also the last three y cells split (three more columns); the nodes
                 off the F = 1 grid take Ê₁ from its spline, not from the quadrature
* I_…            as K but E₁ by quadrature at the extra nodes (same errors, dearer)
* H_…, J_…, X_…  Δ on t, on y graded 1 or 1.25, and with every r or y cell split
                 (to tell which direction limits the error); by name only
* tables.py      what app/integrate/tables.py builds (should equal K_delta_y/αL_r1_y111)

Ê₁ is the F = 1 table of the same lobe and size (tables.build). Candidates on its (r, y)
grid take E₁ at its nodes from it (no extra quadrature); the others compute E₁ at
their own nodes. Each build also evaluates the production check points (CHECK_R + 2
roughness cells × every cell of its μ axis) and reports the production bound
(TABLE_ERROR_SAFETY × seen + node error), so "build s" is comparable with
tables.build's.

Dense independent check (reference: albedo(…, tol=1e-7)), the same points for every
candidate of one size: every r cell (centre ± 40 % seeded jitter) × every cell of the
graded y grid and of the √μ grid (centres ± jitter), the rows α = 1e-4 and α = 1, and a
focused sweep α ∈ {1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2} × μ ∈ {0} ∪ [1e-6, 0.05] (geometric).
Reported: max |Ê_S − E_S| and the (α, μ) where it occurs, and the largest quadrature
error of the reference (the floor of what the check can see).

    python bench/schlick_table.py                 # all configurations (~6 min, 1 core)
    python bench/schlick_table.py --quick         # GGX h-c p = 5 at 56² only
    python bench/schlick_table.py --quick --beckmann H_delta_t5   # named candidates

Timings: wall seconds (CPU seconds of this process, all threads: numba may use both
cores) and integrand evaluations, which the machine's load does not change.
"""
from __future__ import annotations

import sys
import time

import numpy as np
from scipy.interpolate import RectBivariateSpline

sys.path.insert(0, ".")
from app.integrate import tables  # noqa: E402
from app.integrate.albedo import albedo  # noqa: E402
from app.model import make_spec  # noqa: E402

REF_TOL = 1e-7
BLEND = 0.3          # t = BLEND y + (1 − BLEND) √μ


# ---------------------------------------------------------------- axes: μ ↔ s ∈ [0, 1]
def _t_of_mu(mu, alpha, blend=BLEND):
    return blend * tables.y_from_mu(mu, alpha) + (1 - blend) * np.sqrt(mu)


def _mu_of_t(t, alpha, blend=BLEND, iterations=60):
    """Bisection on μ ∈ [0, 1] (t is increasing in μ)."""
    t, alpha = np.broadcast_arrays(np.asarray(t, float), np.asarray(alpha, float))
    lo, hi = np.zeros(t.shape), np.ones(t.shape)
    for _ in range(iterations):
        mid = 0.5 * (lo + hi)
        below = _t_of_mu(mid, alpha, blend) < t
        lo, hi = np.where(below, mid, lo), np.where(below, hi, mid)
    return 0.5 * (lo + hi)


AXES = {
    # name: (nodes(n), s → μ, μ → s)
    "x": (lambda n: np.linspace(0.0, 1.0, n), lambda s, al: np.asarray(s) ** 2,
          lambda mu, al: np.sqrt(mu)),
    "y": (lambda n: np.linspace(0.0, 1.0, n) ** tables.Y_GRADING, tables.mu_from_y,
          tables.y_from_mu),
    "t": (lambda n: np.linspace(0.0, 1.0, n), _mu_of_t, _t_of_mu),
    "y1": (lambda n: np.linspace(0.0, 1.0, n), tables.mu_from_y, tables.y_from_mu),
    "y125": (lambda n: np.linspace(0.0, 1.0, n) ** 1.25, tables.mu_from_y, tables.y_from_mu),
    "t5": (lambda n: np.linspace(0.0, 1.0, n), lambda t, al: _mu_of_t(t, al, 0.5),
           lambda mu, al: _t_of_mu(mu, al, 0.5)),
    "t7": (lambda n: np.linspace(0.0, 1.0, n), lambda t, al: _mu_of_t(t, al, 0.7),
           lambda mu, al: _t_of_mu(mu, al, 0.7)),
}


# ------------------------------------------------------------- representations of E_S
def _ratio(es, e1, m):
    lit = e1 > 0
    limit = es[lit][0] / e1[lit][0] if lit.any() else 1.0
    return np.where(lit, es / np.where(lit, e1, 1.0), limit)


def _w_alpha(al):
    return al


def _w_alog(al):
    return al * (1.0 + np.log(1.0 / al))


REPRESENTATIONS = {
    # name: (needs E₁, to(E_S, E₁, m, α) → value, back(v̂, Ê₁, m, α) → Ê_S)
    "ratio": (True, lambda es, e1, m, al: _ratio(es, e1, m), lambda v, e1, m, al: v * e1),
    "delta": (True, lambda es, e1, m, al: es - e1 * m, lambda v, e1, m, al: v + e1 * m),
    "delta_a": (True, lambda es, e1, m, al: (es - e1 * m) / _w_alpha(al),
                lambda v, e1, m, al: v * _w_alpha(al) + e1 * m),
    "delta_al": (True, lambda es, e1, m, al: (es - e1 * m) / _w_alog(al),
                 lambda v, e1, m, al: v * _w_alog(al) + e1 * m),
    "q": (True, lambda es, e1, m, al: _ratio(es, e1, m) - m,
          lambda v, e1, m, al: (v + m) * e1),
    "direct": (False, lambda es, e1, m, al: es, lambda v, e1, m, al: v),
}

CANDIDATES = {
    # name: (representation, μ axis, extra r nodes per first r cell[, per last μ cell])
    "A_ratio_x": ("ratio", "x", ()),
    "B_delta_y": ("delta", "y", ()),
    "B_delta_y/α": ("delta_a", "y", ()),
    "B_delta_y/αL": ("delta_al", "y", ()),
    "C_q_y": ("q", "y", ()),
    "D_ratio_t": ("ratio", "t", ()),
    "D_direct_t": ("direct", "t", ()),
    "E_direct_y": ("direct", "y", ()),
    "F_delta_x": ("delta", "x", ()),
    "G_delta_y_r1111": ("delta", "y", (1, 1, 1, 1)),
    "G_delta_y_r3211": ("delta", "y", (3, 2, 1, 1)),
    "G_delta_y/αL_r1": ("delta_al", "y", (1,)),
    "G_delta_y/αL_r11": ("delta_al", "y", (1, 1)),
    "K_delta_y/αL_r1": ("delta_al", "y", (1,)),
    "K_delta_y/αL_y111": ("delta_al", "y", (), (1, 1, 1)),
    "K_delta_y/αL_r1_y111": ("delta_al", "y", (1,), (1, 1, 1)),
    "K_delta_y/αL_r11_y111": ("delta_al", "y", (1, 1), (1, 1, 1)),
    "K_delta_y/αL_r1_y1x6": ("delta_al", "y", (1,), (1,) * 6),
    "K_delta_y/αL_r1_y1x14": ("delta_al", "y", (1,), (1,) * 14),
    "K_delta_y_r3211_y111": ("delta", "y", (3, 2, 1, 1), (1, 1, 1)),
    "I_delta_y/αL_r1_y111": ("delta_al", "y", (1,), (1, 1, 1)),
    "H_delta_t": ("delta", "t", ()),
    "H_delta_t5": ("delta", "t5", ()),
    "H_delta_t7": ("delta", "t7", ()),
    "H_delta_t5/αL_r1": ("delta_al", "t5", (1,)),
    "J_delta_y1/αL_r1": ("delta_al", "y1", (1,)),
    "J_delta_y125/αL_r1": ("delta_al", "y125", (1,)),
    "X_delta_y/αL_r1x55_y111": ("delta_al", "y", (1,) * 55, (1, 1, 1)),
    "X_delta_y/αL_r1_y1x55": ("delta_al", "y", (1,), (1,) * 55),
}
#: What a plain run measures (the others by name).
DEFAULT = ["A_ratio_x", "B_delta_y", "C_q_y", "D_ratio_t", "D_direct_t", "E_direct_y",
           "F_delta_x", "B_delta_y/α", "B_delta_y/αL", "G_delta_y/αL_r1", "K_delta_y/αL_r1_y111",
           "tables.py"]


def refined(r, extra):
    """r with cell i split into extra[i] + 1 equal parts."""
    parts = [r[:1]]
    for i in range(r.size - 1):
        k = extra[i] + 1 if i < len(extra) else 1
        parts.append(np.linspace(r[i], r[i + 1], k + 1)[1:])
    return np.concatenate(parts)


class Candidate:
    """A built table of one representation on one axis; ``E(mu, alpha)`` evaluates Ê_S."""

    def __init__(self, name, key_s, base, n, p, seed=0):
        rep, axis, extra, *extra_s = CANDIDATES[name]
        needs_e1, to, self._back = REPRESENTATIONS[rep]
        nodes, self._s_to_mu, self._mu_to_s = AXES[axis]
        self.base, self.p = base, p
        t0, c0 = time.perf_counter(), time.process_time()
        r = refined(np.linspace(tables.ROUGHNESS_MIN, 1.0, n), extra)
        # extra_s: extra nodes in the last cells of the μ axis (listed from the last)
        s = refined(nodes(n)[::-1], extra_s[0])[::-1] if extra_s else nodes(n)
        on_base_y = (np.isin(s, base.y) if axis == "y" and base.y.size == n
                     else np.zeros(s.size, bool))
        values = np.empty((r.size, s.size))
        node_error = 0.0
        self.evaluations = 0
        for i, ri in enumerate(r):
            al = ri * ri
            mu = self._s_to_mu(s, al)
            res_s = albedo(tables._lobe_at(key_s, al), mu, tol=tables.BUILD_TOL)
            self.evaluations += res_s.evaluations
            e1, e1_err = np.zeros(s.size), np.zeros(s.size)
            if needs_e1:
                known = on_base_y & np.isin(ri, base.r)
                if known.any():
                    ir = np.searchsorted(base.r, ri)
                    e1[known] = base.values[ir, np.searchsorted(base.y, s[known])]
                if not known.all() and name.startswith("K"):
                    # the F = 1 table's own spline: reproduced exactly by this table's
                    # spline (its knots are a subset), so no quadrature of E₁ is needed
                    e1[~known] = base.spline.ev(np.full(s.size, ri)[~known], s[~known])
                elif not known.all():
                    res_1 = albedo(tables._lobe_at(base.key, al), mu[~known], tol=tables.BUILD_TOL)
                    e1[~known], e1_err[~known] = res_1.E, res_1.E_error
                    self.evaluations += res_1.evaluations
            values[i] = to(res_s.E, e1, (1 - mu) ** p, al)
            node_error = max(node_error, float(np.max(res_s.E_error + e1_err)))
        self.spline = RectBivariateSpline(r, s, values, kx=3, ky=3, s=0)
        self.r, self.s = r, s
        # the production check points: CHECK_R + 2 roughness cells × every s cell
        rng = np.random.default_rng(seed)
        nr = r.size
        inner = rng.choice(np.arange(1, nr - 2), min(tables.CHECK_R, nr - 3), replace=False)
        ri = np.unique(np.concatenate([[0, nr - 2], inner]))
        measured = 0.0
        for rc in r[ri] + (0.5 + rng.uniform(-0.4, 0.4, ri.size)) * np.diff(r)[ri]:
            sc = s[:-1] + (0.5 + rng.uniform(-0.4, 0.4, s.size - 1)) * np.diff(s)
            mu = self._s_to_mu(sc, rc * rc)
            res = albedo(tables._lobe_at(key_s, rc * rc), mu, tol=tables.BUILD_TOL)
            self.evaluations += res.evaluations
            node_error = max(node_error, float(np.max(res.E_error)))
            measured = max(measured, float(np.max(np.abs(self.E(mu, rc * rc) - res.E))))
        self.seconds = time.perf_counter() - t0
        self.cpu = time.process_time() - c0
        self.bound = tables.TABLE_ERROR_SAFETY * measured + node_error

    def E(self, mu, alpha):
        mu, alpha = np.broadcast_arrays(np.asarray(mu, float), np.asarray(alpha, float))
        r = np.clip(np.sqrt(alpha), self.r[0], self.r[-1])
        s = self._mu_to_s(mu, np.clip(alpha, self.r[0] ** 2, 1.0))
        e1 = self.base.E(mu, alpha)
        v = self.spline.ev(r, s)
        return np.clip(self._back(v, e1, (1 - mu) ** self.p, r * r), 0.0, 1.0)


# ------------------------------------------------------------------------ dense check
def check_points(n, seed=7):
    """(α, μ) arrays: every r cell × (every graded-y cell ∪ every √μ cell) of size n,
    jittered centres; the rows α = 1e-4 and 1; the small-α grazing sweep."""
    rng = np.random.default_rng(seed)
    r = np.linspace(tables.ROUGHNESS_MIN, 1.0, n)
    y = AXES["y"][0](n)
    x = AXES["x"][0](n)
    alphas, mus = [], []

    def cells(g):
        return g[:-1] + (0.5 + rng.uniform(-0.4, 0.4, g.size - 1)) * np.diff(g)
    r_rows = np.concatenate([cells(r), [r[0], 1.0]])
    for rc in r_rows:
        al = rc * rc
        mu = np.concatenate([tables.mu_from_y(cells(y), al), cells(x) ** 2])
        alphas.append(np.full(mu.size, al))
        mus.append(mu)
    sweep_mu = np.concatenate([[0.0], np.geomspace(1e-6, 0.05, 60)])
    for al in (1e-4, 3e-4, 1e-3, 3e-3, 1e-2, 3e-2):
        alphas.append(np.full(sweep_mu.size, al))
        mus.append(sweep_mu)
    return np.concatenate(alphas), np.concatenate(mus)


def reference(key_s, alpha, mu):
    E, err = np.empty(mu.size), np.empty(mu.size)
    for al in np.unique(alpha):
        sel = alpha == al
        res = albedo(tables._lobe_at(key_s, float(al)), mu[sel], tol=REF_TOL)
        E[sel], err[sel] = res.E, res.E_error
    return E, err


def dense(cand, alpha, mu, ref):
    est = np.concatenate([cand.E(mu[alpha == al], al) for al in np.unique(alpha)])
    order = np.concatenate([np.flatnonzero(alpha == al) for al in np.unique(alpha)])
    err = np.empty(mu.size)
    err[order] = np.abs(est - ref[order])
    k = int(np.argmax(err))
    return err[k], alpha[k], mu[k]


class Production:
    """tables.build of the Schlick basis on ``base``, timed like the candidates."""

    def __init__(self, key_s, base):
        t0, c0 = time.perf_counter(), time.process_time()
        self.table = tables.build(key_s, base=base)
        self.seconds, self.cpu = time.perf_counter() - t0, time.process_time() - c0
        self.bound, self.evaluations = self.table.error, self.table.build_evaluations

    def E(self, mu, alpha):
        return self.table.E(mu, alpha)


def row(lobe, p, n, name, found, bound, seconds, cpu, evaluations, ref_err):
    err, a_at, mu_at = found
    print(f"| {lobe} | {p:g} | {n} | {name} | {err:.2e} | {a_at:.1e}, {mu_at:.2e} | "
          f"{bound:.2e} | {seconds:.2f} ({cpu:.2f}) | {evaluations / 1e6:.0f} M | "
          f"{ref_err:.1e} |", flush=True)


def main() -> None:
    quick = "--quick" in sys.argv
    beck = "--beckmann" in sys.argv
    configs = [("ggx", "height_correlated", 5.0, (32, 48, 56, 64)),
               ("beckmann", "height_correlated", 5.0, (32, 56)),
               ("ggx", "separable", 5.0, (56,)),
               ("beckmann", "separable", 5.0, (56,)),
               ("ggx", "height_correlated", 3.0, (56,)),
               ("beckmann", "height_correlated", 3.0, (56,))]
    if quick:
        configs = [("beckmann" if beck else "ggx", "height_correlated", 5.0, (56,))]
    names = [a for a in sys.argv[1:] if a in CANDIDATES or a == "tables.py"] or DEFAULT
    print("| lobe | p | n | candidate | dense max error | at α, μ | reported bound | build s (CPU) "
          "| evaluations | ref err |")
    print("|---|---|---|---|---|---|---|---|---|---|")
    for ndf, g2, p, sizes in configs:
        lobe = make_spec(ndf=ndf, alpha=0.3, fresnel="none", g2=g2).brdf()
        key1 = tables.table_key(lobe)
        key_s = tables.table_key(lobe, p)
        albedo(lobe, [0.5])                       # compile outside the timings
        for n in sizes:
            c0 = time.process_time()
            base = tables.build(key1, n, n)
            base_cpu = time.process_time() - c0
            alpha, mu = check_points(n)
            ref, ref_err = reference(key_s, alpha, mu)
            for name in names:
                if name == "tables.py":
                    cand = Production(key_s, base)
                else:
                    cand = Candidate(name, key_s, base, n, p)
                row(f"{ndf} {g2[:3]}", p, n, name, dense(cand, alpha, mu, ref), cand.bound,
                    cand.seconds, cand.cpu, cand.evaluations, ref_err.max())
            ref1, ref1_err = reference(key1, alpha, mu)
            row(f"{ndf} {g2[:3]}", p, n, "(F = 1 table Ê₁)", dense(base, alpha, mu, ref1),
                base.error, base.build_seconds, base_cpu, base.build_evaluations, ref1_err.max())


if __name__ == "__main__":
    main()
