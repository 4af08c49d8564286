"""Summaries: E(μ) of tabulated and scattered data inside its stated error bar (against
E of the closed-form model by adaptive quadrature), reciprocity errors found."""
import io

import numpy as np
from scipy import integrate

from app.datasets import formats, summary

from . import known


def E_reference(mu, f0):
    """E(μ_v) = ∫∫ f(l, v) cos θ_l sin θ_l dθ_l dφ_l of the closed form, by scipy's
    adaptive quadrature (φ_v = 0; the lobe is symmetric in φ_l, so 2 × [0, π])."""
    v = np.array([np.sqrt(1 - mu * mu), 0.0, mu])

    def inner(phi):
        def g(theta):
            l = np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])
            return known.ggx_f(l, v, f0=f0) * np.cos(theta) * np.sin(theta)
        return integrate.quad(g, 0, np.pi / 2, limit=200, epsabs=1e-10)[0]
    return 2 * integrate.quad(inner, 0, np.pi, limit=200, epsabs=1e-9)[0]


def test_merl_albedo_is_within_its_error_bar():
    info = summary.summarize(formats.load(known.merl_bytes()))
    assert info["fraction_measured"] > 0.7 and info["channels"] == ["r", "g", "b"]
    albedo = info["albedo"]
    for k in (1, 4, 9):              # μ = 0.2, 0.5, 1.0
        mu = albedo["mu"][k]
        for c in "rb":
            E, err = albedo["E"][c][k], albedo["E_error"][c][k]
            ref = E_reference(mu, known.F0[c])
            assert abs(E - ref) <= err, (mu, c, E, ref, err)
            assert err < 0.05 * ref       # and the bar is useful (it is conservative)
    assert info["reciprocity"]["max_relative_error"] == 0.0


def samples_text(f, theta, phi):
    rows = []
    for ti in theta:
        for pi in phi:
            for to in (20.0, 60.0):
                l = np.array([np.sin(np.radians(ti)) * np.cos(np.radians(pi)),
                              np.sin(np.radians(ti)) * np.sin(np.radians(pi)), np.cos(np.radians(ti))])
                v = np.array([np.sin(np.radians(to)), 0.0, np.cos(np.radians(to))])
                rows.append((ti, pi, to, 0.0, f(l, v)))
    out = io.StringIO()
    np.savetxt(out, rows, delimiter=",", fmt="%.17g", header="theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f",
               comments="")
    return out.getvalue().encode()


def test_scattered_albedo_is_within_its_error_bar():
    theta = np.linspace(0, 89.5, 60)
    phi = np.arange(0, 360, 6.0)
    info = summary.summarize(formats.load(samples_text(lambda l, v: known.ggx_f(l, v, alpha=0.4), theta, phi)))
    albedo = info["albedo"]
    assert albedo["mu"] == [np.cos(np.radians(60.0)), np.cos(np.radians(20.0))]
    for k, mu in enumerate(albedo["mu"]):
        E, err = albedo["E"]["f"][k], albedo["E_error"]["f"][k]
        v = np.array([np.sqrt(1 - mu * mu), 0.0, mu])

        def g(theta, phi):
            l = np.array([np.sin(theta) * np.cos(phi), np.sin(theta) * np.sin(phi), np.cos(theta)])
            return known.ggx_f(l, v, alpha=0.4) * np.cos(theta) * np.sin(theta)
        ref = integrate.dblquad(g, 0, 2 * np.pi, 0, np.pi / 2, epsabs=1e-8)[0]
        assert abs(E - ref) <= err < 0.05 * ref, (mu, E, ref, err)


def test_a_non_reciprocal_dump_shows_its_error_where_it_is():
    """f(l, v) with F taken at l·n instead of v·h is not reciprocal; the summary finds the
    swapped pairs and the largest error."""
    rows = ["theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f"]
    for ti in (10.0, 40.0, 70.0):
        for to in (10.0, 40.0, 70.0):
            f = 0.1 + 0.5 * (1 - np.cos(np.radians(ti))) ** 2   # depends on θ_i only
            rows.append(f"{ti},0,{to},180,{float(f)!r}")
    info = summary.summarize(formats.load("\n".join(rows).encode()))
    rec = info["reciprocity"]
    assert rec["pairs"] == 3
    f = lambda t: 0.1 + 0.5 * (1 - np.cos(np.radians(t))) ** 2
    assert np.isclose(rec["max_relative_error"], (f(70) - f(10)) / f(70))
    assert {rec["where"]["theta_i_deg"], rec["where"]["theta_o_deg"]} == {10.0, 70.0}


def test_term_summary_checks_the_normalisation_of_D():
    theta = np.linspace(0, 90, 721)
    t = np.radians(theta)
    alpha = 0.3
    D = alpha ** 2 / (np.pi * (np.cos(t) ** 2 * (alpha ** 2 - 1) + 1) ** 2)   # GGX
    text = "theta_deg,D\n" + "\n".join(f"{a:.17g},{d:.17g}" for a, d in zip(theta, D))
    info = summary.summarize(formats.load(text.encode()))
    norm = info["D_normalisation"]
    assert abs(norm["value"] - 1.0) <= norm["error"] + 1e-6 and norm["error"] < 1e-3
    wrong = "theta_deg,D\n" + "\n".join(f"{a:.17g},{2 * d:.17g}" for a, d in zip(theta, D))
    assert abs(summary.summarize(formats.load(wrong.encode()))["D_normalisation"]["value"] - 2) < 1e-3
