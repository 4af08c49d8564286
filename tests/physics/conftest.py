"""Shared fixtures and quadrature helpers for the physics tests.

Everything here is written from the definitions, independently of ``app.integrate``:
the rules below are plain Gauss-Legendre products after a change of variables chosen
only to put nodes where the integrands vary (the peak of D, the kinks where a
positive part switches on). None of them assumes an identity that is under test.

Conventions (docs/conventions.md): n = +z, ω = (sinθ cosφ, sinθ sinφ, cosθ), μ = cosθ, directions
point away from the surface, α is the roughness of the formulas.
"""
from __future__ import annotations

from functools import lru_cache

import numpy as np
import pytest

from app.physics.brdf import BRDF
from app.physics.fresnel import FRESNELS
from app.physics.g2 import G2_FORMS
from app.physics.masking import MASKINGS
from app.physics.ndf import NDFS
from app.physics.ndf import make_ndf as _make_ndf

# (α_x, α_y): isotropic from 1e-3 to 1 and two anisotropic pairs (10:1 either way).
ALPHA_PAIRS = [(1e-3, 1e-3), (0.01, 0.01), (0.3, 0.3), (1.0, 1.0), (0.05, 0.5), (1.0, 0.1)]


def _ids(pair):
    return f"ax{pair[0]:g}-ay{pair[1]:g}"


def _valid(ndf_name, pair):
    """An anisotropic pair only for NDFs that have an anisotropic form (shape-invariant)."""
    return pair[0] == pair[1] or NDFS[ndf_name].anisotropic


def pytest_generate_tests(metafunc):
    """``ndf_name`` is every registered NDF and ``alphas`` every (α_x, α_y) pair, isotropic
    and anisotropic; together, only the combinations the NDF accepts."""
    explicit = set()
    for mark in metafunc.definition.iter_markers("parametrize"):
        argnames = mark.args[0]
        explicit.update(a.strip() for a in (argnames.split(",") if isinstance(argnames, str) else argnames))
    names = [n for n in metafunc.fixturenames if n not in explicit]
    if "ndf_name" in names and "alphas" in names:
        combos = [(n, a) for n in sorted(NDFS) for a in ALPHA_PAIRS if _valid(n, a)]
        metafunc.parametrize(("ndf_name", "alphas"), combos,
                             ids=[f"{n}-{_ids(a)}" for n, a in combos])
    elif "ndf_name" in names:
        metafunc.parametrize("ndf_name", sorted(NDFS))
    elif "alphas" in names:
        metafunc.parametrize("alphas", ALPHA_PAIRS, ids=[_ids(a) for a in ALPHA_PAIRS])


def make_ndf(ndf_name, alpha, alpha_y=None, **shape):
    """The registry's make_ndf, except that an NDF with no anisotropic form (not
    shape-invariant: GTR, Blinn-Phong) is built at α_y = α_x: the extreme-value tests
    that ask for anisotropic pairs then test it isotropically."""
    if not NDFS[ndf_name].anisotropic:
        alpha_y = None
    return _make_ndf(ndf_name, alpha, alpha_y, **shape)


def exact_smith(ndf_name):
    """The masking that is exact Smith for this NDF: ``smith`` unless the NDF's Λ is an
    approximation (Blinn-Phong), then ``smith_numeric``."""
    return MASKINGS["smith" if NDFS[ndf_name].smith_exact else "smith_numeric"]


def make_brdf(ndf_name, alpha, alpha_y=None, g2="height_correlated", fresnel="none",
              kd=0.0, **fresnel_params):
    """BRDF(make_ndf(..), exact Smith, G2 form, Fresnel, kd) as the brief prescribes."""
    return BRDF(make_ndf(ndf_name, alpha, alpha_y), exact_smith(ndf_name), G2_FORMS[g2],
                FRESNELS[fresnel](**fresnel_params), kd)


# ----------------------------------------------------------------------------- rules

@lru_cache(maxsize=None)
def _gauss01_cached(n):
    x, w = np.polynomial.legendre.leggauss(n)
    x, w = 0.5 * (x + 1.0), 0.5 * w
    x.flags.writeable = False
    w.flags.writeable = False
    return x, w


def gauss01(n):
    """n-point Gauss-Legendre rule on [0, 1] (numpy's nodes, not app.integrate's)."""
    return _gauss01_cached(int(n))


def gauss_on(a, b, n):
    """Gauss-Legendre nodes/weights on [a, b]; a, b may be arrays (...,): returns (..., n)."""
    t, wt = gauss01(n)
    a = np.asarray(a, dtype=float)[..., None]
    b = np.asarray(b, dtype=float)[..., None]
    return a + (b - a) * t, (b - a) * wt


def graded_on(a, b, n, scale, toward="a"):
    """Gauss rule on [a, b] (arrays allowed) clustered at one end with length scale ``scale``.

    x = end ± scale·tan(t), t ∈ [0, atan((b − a)/scale)], dx = scale sec²t dt: the node
    density near the end is ~ n/scale and falls off like 1/distance, so a bump of width
    ``scale`` at the end and its power-law tails are both resolved.
    """
    a = np.asarray(a, dtype=float)
    b = np.asarray(b, dtype=float)
    scale = np.asarray(scale, dtype=float)
    tmax = np.arctan((b - a) / scale)
    t, wt = gauss_on(np.zeros_like(tmax), tmax, n)
    d = scale[..., None] * np.tan(t)
    w = wt * scale[..., None] / np.cos(t) ** 2
    x = (a[..., None] + d) if toward == "a" else (b[..., None] - d)
    return x, w


def alpha_radial(ax, ay, phi):
    """Stretched radius α̃(φ) = (cos²φ/α_x² + sin²φ/α_y²)^(−1/2): the slope scale of D
    along azimuth φ (for D the exponent/denominator is tan²θ/α̃(φ)², Heitz 2014 eq. 83, 85)."""
    return 1.0 / np.sqrt(np.cos(phi) ** 2 / ax ** 2 + np.sin(phi) ** 2 / ay ** 2)


def m_hemisphere_rule(ax, ay, n_beta=96, n_phi=96, v=None, beta_max=0.5 * np.pi):
    """Nodes m (N, 3) and weights (N,) for ∫_{H²} g(m) dm, the upper hemisphere of m.

    Variables: φ_m, and β ∈ [0, π/2) with tanθ_m = α̃(φ) tanβ (the peak of D at θ_m = 0
    is spread over the whole β range for any α). dm = sinθ dθ dφ with
    dθ/dβ = α̃ / (cos²β + α̃² sin²β).

    φ is split at the axes (where α̃(φ) has its extrema) and, if ``v`` is given, at the
    two azimuths where v·m = 0 reaches θ_m = 90°; β is split where v·m changes sign, so
    integrands containing (v·m)⁺ are smooth on every piece.

    tanβ is the stretched slope radius r̃ = √(x̃² + ỹ²) of m (Heitz 2014 sec. 5), so
    ``beta_max`` < π/2 (without ``v``) restricts the rule to the slopes r̃ ≤ tan(beta_max).
    """
    cuts = [0.0, 0.5 * np.pi, np.pi, 1.5 * np.pi]
    if v is not None:
        v = np.asarray(v, dtype=float)
        if np.hypot(v[0], v[1]) > 0:
            pv = np.arctan2(v[1], v[0])
            cuts += [np.mod(pv + 0.5 * np.pi, 2 * np.pi), np.mod(pv - 0.5 * np.pi, 2 * np.pi)]
    cuts = np.unique(np.round(np.asarray(cuts), 15))
    cuts = np.append(cuts, cuts[0] + 2 * np.pi)
    phi, wphi = gauss_on(cuts[:-1], cuts[1:], n_phi)
    phi, wphi = phi.ravel(), wphi.ravel()
    A = alpha_radial(ax, ay, phi)
    # β split point: where v·m = 0, i.e. μ_v + tanθ (v_x cosφ + v_y sinφ) = 0.
    beta_cut = np.full_like(phi, 0.5 * beta_max)
    if v is not None:
        c = v[0] * np.cos(phi) + v[1] * np.sin(phi)
        neg = c < 0
        tan_theta_star = v[2] / np.where(neg, -c, 1.0)
        beta_cut = np.where(neg, np.arctan2(tan_theta_star, A), beta_cut)
    b1, w1 = gauss_on(np.zeros_like(phi), beta_cut, n_beta)
    b2, w2 = gauss_on(beta_cut, np.full_like(phi, beta_max), n_beta)
    beta = np.concatenate([b1, b2], axis=1)
    wbeta = np.concatenate([w1, w2], axis=1)
    A2 = A[:, None]
    theta = np.arctan2(A2 * np.sin(beta), np.cos(beta))
    dtheta = A2 / (np.cos(beta) ** 2 + (A2 * np.sin(beta)) ** 2)
    st, ct = np.sin(theta), np.cos(theta)
    P = np.broadcast_to(phi[:, None], beta.shape)
    m = np.stack([st * np.cos(P), st * np.sin(P), ct], axis=-1).reshape(-1, 3)
    w = (st * dtheta * wbeta * wphi[:, None]).ravel()
    return m, w


def _piece(a, b, n, scale, grade):
    """Per-row rule on [a, b] (arrays (k,)); ``grade`` (k,) of "a", "b" or "" says which
    end, if any, the nodes cluster at. Returns (k, n) nodes and weights."""
    xg, wg = gauss_on(a, b, n)
    xa, wa = graded_on(a, b, n, scale, "a")
    xb, wb = graded_on(a, b, n, scale, "b")
    ga, gb = (grade == "a")[:, None], (grade == "b")[:, None]
    x = np.where(ga, xa, np.where(gb, xb, xg))
    w = np.where(ga, wa, np.where(gb, wb, wg))
    return x, w


def l_sphere_rule(v, scale, n_theta=120, n_psi=120):
    """Nodes l (N, 3) and weights (N,) for ∫_{S²} g(l) dl over the FULL sphere of l.

    Spherical coordinates (θ', ψ) about v: l = cosθ' v + sinθ' (cosψ e1 + sinψ e2),
    dl = sinθ' dθ' dψ, with e1 the direction of n seen from v (so the mirror direction
    r = 2μ_v n − v sits at θ' = 2θ_v, ψ = 0). In these coordinates h = (l+v)/‖l+v‖
    is a smooth function everywhere, also at l = −v (the pole θ' = π).

    θ' is split at the peak 2θ_v (graded towards it with ``2·scale``) and at the curve
    where h crosses the horizon (D of a long-tailed NDF jumps to 0 there); ψ is split at
    the peak (graded with ``scale/sinθ_v``) and where that curve starts (ψ = ±π/2).
    """
    v = np.asarray(v, dtype=float)
    mu_v = v[2]
    sin_v = np.hypot(v[0], v[1])
    if sin_v > 0:
        e1 = np.array([0.0, 0.0, 1.0]) - mu_v * v
        e1 /= np.linalg.norm(e1)
    else:
        e1 = np.array([1.0, 0.0, 0.0])
    e2 = np.cross(v, e1)
    theta_p = 2.0 * np.arctan2(sin_v, mu_v)          # angle between v and r
    c_psi = min(scale / sin_v, 1.0) if sin_v > 0 else 1.0
    # ψ pieces: [0, π/2], [π/2, π] graded to 0 / plain, and mirror images.
    p1, w1 = graded_on(0.0, 0.5 * np.pi, n_psi, c_psi, "a")
    p2, w2 = gauss_on(0.5 * np.pi, np.pi, n_psi)
    psi = np.concatenate([p1, p2, -p1, -p2])
    wpsi = np.concatenate([w1, w2, w1, w2])
    # h_z = μ_v cos(θ'/2) + sin(θ'/2) u_z, u_z = cosψ (e1)_z: horizon crossing θ*(ψ)
    uz = np.cos(psi) * e1[2]
    crossing = uz < 0
    theta_star = np.where(crossing, 2.0 * np.arctan2(mu_v, np.where(crossing, -uz, 1.0)), np.pi)
    lo = np.minimum(theta_p, theta_star)
    hi = np.maximum(theta_p, theta_star)
    peak_first = theta_p <= theta_star                # the peak is at lo, else at hi
    zero = np.zeros_like(lo)
    pi = np.full_like(lo, np.pi)
    c = np.full_like(lo, 2.0 * scale)
    pieces = [
        # (a, b, where to grade: "b" end if the peak is there, else none)
        _piece(zero, lo, n_theta, c, np.where(peak_first, "b", "")),
        _piece(lo, hi, n_theta, c, np.where(peak_first, "a", "b")),
        _piece(hi, pi, n_theta, c, np.where(peak_first, "", "a")),
    ]
    th = np.concatenate([p[0] for p in pieces], axis=1)
    wth = np.concatenate([p[1] for p in pieces], axis=1)
    P = np.broadcast_to(psi[:, None], th.shape)
    u = np.cos(P)[..., None] * e1 + np.sin(P)[..., None] * e2
    l = np.cos(th)[..., None] * v + np.sin(th)[..., None] * u
    w = np.sin(th) * wth * wpsi[:, None]
    return l.reshape(-1, 3), w.ravel()


def random_upper_directions(rng, n, grazing_fraction=0.1):
    """n random directions in the closed upper hemisphere, some exactly grazing."""
    mu = rng.uniform(0.0, 1.0, n)
    mu[rng.uniform(size=n) < grazing_fraction] = 0.0
    phi = rng.uniform(0.0, 2 * np.pi, n)
    s = np.sqrt(1.0 - mu * mu)
    return np.stack([s * np.cos(phi), s * np.sin(phi), mu], axis=-1)


@pytest.fixture
def rng():
    return np.random.default_rng(20240611)
