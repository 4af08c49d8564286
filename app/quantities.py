"""The arrays behind each view: what a data endpoint returns and a figure draws.

One function per view; each evaluates only what its view shows. Angles arrive in
degrees (API units) and are converted here, once.
"""
from __future__ import annotations

import numpy as np

from .integrate.methods import albedo_by
from .physics.brdf import BRDF
from .physics.masking import G1
from .physics.numeric import where_valid
from .physics.vectors import direction_deg


def evaluate(brdf: BRDF, theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg, want) -> dict:
    """BRDF terms at direction pairs (i = light l, o = view v), broadcast together."""
    l = direction_deg(theta_i_deg, phi_i_deg)
    v = direction_deg(theta_o_deg, phi_o_deg)
    l, v = np.broadcast_arrays(l, v)
    return brdf.evaluate(l, v, want)


def ndf_curve(brdf: BRDF, phi_deg: float, n: int, cosine: bool = False) -> dict:
    """D(θ_m) for θ_m = 0..90° (both ends) at azimuth φ; with ``cosine``, D·cos θ_m
    (the projected-area density: ∫ D cos θ_m dω_m = 1, Walter et al. 2007 eq. 4)."""
    theta = np.linspace(0.0, 90.0, n)
    m = direction_deg(theta, phi_deg)
    D = brdf.ndf.D(m)
    return {"theta_deg": theta, "D_cos": D * m[..., 2]} if cosine else {"theta_deg": theta, "D": D}


def g1_curve(brdf: BRDF, phi_deg: float, n: int) -> dict:
    """Λ(θ_v) and G1(θ_v) = 1/(1+Λ) for θ_v = 0..90° at azimuth φ (Λ = +inf at 90°).

    When the masking is not ``smith``, also G1_exact (the NDF's own Smith G1) and
    G1_error = G1 − G1_exact, so an approximation is always shown with its error."""
    theta = np.linspace(0.0, 90.0, n)
    w = direction_deg(theta, phi_deg)
    ml = brdf.masking.mu_Lambda(brdf.ndf, w)
    mu = w[..., 2]
    Lambda = np.divide(ml, mu, out=np.full_like(mu, np.inf), where=mu > 0)
    out = {"theta_deg": theta, "Lambda": Lambda, "G1": G1(mu, ml)}
    if brdf.masking.name != "smith":
        out["G1_exact"] = G1(mu, brdf.ndf.mu_Lambda(w))
        out["G1_error"] = out["G1"] - out["G1_exact"]
    return out


def lobe_curve(brdf: BRDF, theta_i_deg: float, phi_i_deg: float, n: int, cosine: bool) -> dict:
    """f in the plane of incidence, θ_o from −90° to 90°; θ_o > 0 on the mirror side
    (azimuth φ_i + 180°). ``cosine`` multiplies by cos θ_i."""
    theta_o = np.linspace(-90.0, 90.0, n)
    phi_o = np.where(theta_o >= 0, phi_i_deg + 180.0, phi_i_deg)
    f = evaluate(brdf, theta_i_deg, phi_i_deg, np.abs(theta_o), phi_o, ("f",))["f"]
    if cosine:
        return {"theta_o_deg": theta_o, "f_cos": f * np.sin(np.deg2rad(90.0 - theta_i_deg))}
    return {"theta_o_deg": theta_o, "f": f}


def lobe_grid(brdf: BRDF, theta_i_deg: float, phi_i_deg: float, n_theta: int, n_phi: int) -> dict:
    """f over the hemisphere of v: θ_v = 0..90° (n_theta), φ_v = 0..360° (n_phi)."""
    theta = np.linspace(0.0, 90.0, n_theta)
    phi = np.linspace(0.0, 360.0, n_phi)
    f = evaluate(brdf, theta_i_deg, phi_i_deg, theta[:, None], phi[None, :], ("f",))["f"]
    return {"theta_deg": theta, "phi_deg": phi, "f": f}


def albedo_curve(brdf: BRDF, mu, phi_deg: float, tol: float, method: str = "quadrature",
                 order: int | None = None, samples: int = 1024, seed: int = 0) -> dict:
    """E(μ) at the given cosines and E_avg over [0, 1], with errors and cost, by
    ``method`` (integrate/methods.py; quadrature by default). With Kulla-Conty
    compensation E is single + multiple scattering and E_single is reported too."""
    return albedo_by(brdf, mu, np.deg2rad(phi_deg), method, tol, order, samples, seed)


def g2_grid(brdf: BRDF, phi_deg: float, n: int) -> dict:
    """G2(l, v) over θ_l, θ_v = 0..90° (n each; rows θ_l, columns θ_v), with l at
    azimuth 0 (along t, the direction of α_x) and v at azimuth φ: φ is the azimuth
    difference of the direction-correlated forms."""
    theta = np.linspace(0.0, 90.0, n)
    G2 = evaluate(brdf, theta[:, None], 0.0, theta[None, :], phi_deg, ("G2",))["G2"]
    return {"theta_l_deg": theta, "theta_v_deg": theta, "G2": G2}


def fresnel_curve(brdf: BRDF, n: int) -> dict:
    """F(θ) for θ = 0..90° (θ the angle between v and h), its cosine-weighted average,
    and — for an approximation (Schlick) — the exact form it stands for (the dielectric
    of the same F₀) and the error F − F_exact."""
    theta = np.linspace(0.0, 90.0, n)
    cos_theta = direction_deg(theta, 0.0)[..., 2]   # exactly 0 at 90°
    F = brdf.fresnel.F(cos_theta)
    out = {"theta_deg": theta, "F": F, "F_avg": brdf.fresnel.F_avg()}
    exact = brdf.fresnel.exact_counterpart()
    if exact is not None:
        F_exact = exact.F(cos_theta)
        out.update({"F_exact": F_exact, "F_error": F - F_exact,
                    "F_exact_model": {"fresnel": exact.name,
                                      **{p.name: getattr(exact, p.name) for p in exact.params}}})
    return out


def lit_sphere(brdf: BRDF, theta_i_deg: float, phi_i_deg: float, n: int) -> dict:
    """A sphere lit by one directional light, seen by an orthographic viewer along +z:
    radiance per unit irradiance L_o/E = f(l, v)·⟨n·l⟩ (1/sr) at n×n pixel centres
    (rows y, columns x, in sphere radii; NaN off the sphere).

    Camera frame: v = +z; the light's polar angle θ_i is measured from v, its azimuth
    φ_i in the image plane from +x. At each pixel the surface normal is
    n = (x, y, √(1−x²−y²)) and the tangent t is +x projected onto the tangent plane
    (the direction of α_x; it is undefined only at n = ±x, on the silhouette, which
    no pixel centre reaches). Local directions are (·t, ·b, ·n), b = n × t.
    """
    centres = -1.0 + (2.0 * np.arange(n) + 1.0) / n
    y, x = np.meshgrid(centres[::-1], centres, indexing="ij")   # row 0 at the top
    on = x * x + y * y < 1.0
    normal = np.stack([x[on], y[on], np.sqrt(1.0 - x[on] ** 2 - y[on] ** 2)], axis=-1)
    ex = np.array([1.0, 0.0, 0.0])
    t = ex - normal[:, :1] * normal
    t /= np.linalg.norm(t, axis=-1, keepdims=True)
    b = np.cross(normal, t)
    frame = np.stack([t, b, normal], axis=-2)            # rows: t, b, n
    light = direction_deg(theta_i_deg, phi_i_deg)
    view = np.array([0.0, 0.0, 1.0])
    l, v = frame @ light, frame @ view
    mu_l = l[:, 2]
    lit = mu_l > 0.0
    value = np.zeros(mu_l.shape)
    if lit.any():
        value[lit] = brdf.evaluate(l[lit], v[lit], ("f",))["f"] * mu_l[lit]
    radiance = np.full(x.shape, np.nan)
    radiance[on] = value
    return {"y": centres[::-1], "x": centres, "radiance": radiance}


def rusinkiewicz_directions(theta_h_deg, phi_h_deg, theta_d_deg, phi_d_deg):
    """l and v from the half/difference angles (Rusinkiewicz 1998, sec. 3): the
    difference vector d = (θ_d, φ_d) in the frame where h is the pole is rotated by
    R_z(φ_h) R_y(θ_h); l = that rotation of d, v = of d mirrored about h."""
    # sines and cosines exact at multiples of 90° (direction_deg takes care of that)
    polar, azimuth = direction_deg(theta_h_deg, 0.0), direction_deg(90.0, phi_h_deg)
    st, ct = polar[..., :1], polar[..., 2:]
    cp, sp = azimuth[..., :1], azimuth[..., 1:2]
    d = direction_deg(theta_d_deg, phi_d_deg)

    def rotate(w):
        x = w[..., :1] * ct + w[..., 2:] * st          # R_y(θ_h)
        z = -w[..., :1] * st + w[..., 2:] * ct
        y = w[..., 1:2]
        return np.concatenate([x * cp - y * sp, x * sp + y * cp, z], axis=-1)   # R_z(φ_h)

    mirrored = d * np.array([-1.0, -1.0, 1.0])
    return rotate(d), rotate(mirrored)


def half_difference_slice(brdf: BRDF, phi_h_deg: float, phi_d_deg: float, n: int,
                          cosine: bool) -> dict:
    """f (or f·cos θ_l) over θ_h, θ_d = 0..90° at fixed φ_h, φ_d: the "image slice" of
    the Disney BRDF Explorer (Burley 2012, fig. 3). Rows θ_d, columns θ_h; NaN where
    l or v is below the horizon (no such pair of directions exists)."""
    theta = np.linspace(0.0, 90.0, n)
    l, v = rusinkiewicz_directions(theta[None, :], phi_h_deg, theta[:, None], phi_d_deg)
    l, v = np.broadcast_arrays(l, v)
    above = (l[..., 2] >= 0.0) & (v[..., 2] >= 0.0)
    f = np.full(above.shape, np.nan)
    if above.any():
        value = brdf.evaluate(l[above], v[above], ("f",))["f"]
        if cosine:
            # f·cos θ_l is 0 at θ_l = 90° even where f diverges (both directions grazing)
            mu_l = l[above][:, 2]
            value = where_valid(mu_l > 0.0, [value, mu_l], lambda a, b: a * b, 0.0)
        f[above] = value
    return {"theta_d_deg": theta, "theta_h_deg": theta, ("f_cos" if cosine else "f"): f}


def samples(brdf: BRDF, sampler: str, n: int, seed: int, theta_i_deg: float, phi_i_deg: float) -> dict:
    """n directions l drawn by ``sampler`` for the fixed direction at (θ_i, φ_i) (the v of
    the sampler), with pdf(l) (per steradian, over the whole sphere) and the Monte Carlo
    weight f·cos θ_l/pdf (0 below the horizon), whose mean is the albedo estimate E.
    The χ² goodness of fit of the samples against the pdf is on SAMPLE_BINS uniform
    (cos θ, φ) bins plus one cell below the horizon, expected counts by Gauss rules."""
    from .integrate.montecarlo import SAMPLERS, weights
    from .integrate.sampling import goodness_of_fit
    v = direction_deg(theta_i_deg, phi_i_deg)
    chosen = SAMPLERS[sampler]
    l, pdf, w = weights(brdf, chosen, v[None, :], n, seed)
    l, pdf, w = l[0], pdf[0], w[0]
    n_cos, n_phi = SAMPLE_BINS
    fit = goodness_of_fit(l, lambda x: chosen.pdf(brdf, x, v), np.linspace(0.0, 1.0, n_cos + 1),
                          np.linspace(-np.pi, np.pi, n_phi + 1))
    return {"x": l[:, 0], "y": l[:, 1], "z": l[:, 2], "pdf": pdf, "weight": w,
            "E": float(w.mean()), "E_error": float(w.std(ddof=1) / np.sqrt(n)),
            "chi2": fit["chi2"], "dof": fit["dof"], "p_value": fit["p_value"],
            "below_horizon": fit["below"], "below_horizon_expected": float(fit["below_expected"]),
            "sampler": sampler, "seed": seed}


#: (cos θ, φ) bins of the χ² test of /samples: uniform in both, so equal solid angles.
SAMPLE_BINS = (16, 32)
