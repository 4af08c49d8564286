"""The arrays behind each view: what a data endpoint returns and a figure draws.

One function per view; each evaluates only what its view shows. Angles arrive in
degrees (API units) and are converted here, once.
"""
from __future__ import annotations

import numpy as np

from . import kernels
from .adaptive import ladder, peak, refine_curve, refine_grid
from .integrate import cost
from .integrate.methods import albedo_by
from .materials import evaluate_rgb
from .model import make_spec
from .physics.brdf import BRDF
from .physics.masking import G1
from .physics.numeric import where_valid
from .physics.vectors import direction_deg
from .shader.conventions import ALPHA_MAX, ALPHA_MIN, table


#: Direction pairs evaluated at once. Every model's temporaries take 100–250 bytes a
#: pair (tracemalloc, all six quantities, two lobes, smith_numeric, direction-correlated
#: G2), so a chunk holds ≤ ~16 MB whatever the request's size; the per-call overhead of a
#: chunk is ~0.1 ms against its ~10 ms of work.
EVAL_CHUNK = 65536


#: bytes a pair's temporaries take at most (measured 100–250), and bytes one returned
#: value costs until it is sent (8 in its array, ~24 as JSON text)
BYTES_PER_PAIR = 250
BYTES_PER_VALUE = 32


def evaluate(brdf: BRDF, theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg, want,
             param: str = "n") -> dict:
    """BRDF terms at direction pairs (i = light l, o = view v), broadcast together, in
    chunks of EVAL_CHUNK pairs (the peak memory is the outputs plus one chunk's). Work
    that cannot fit the request's budgets is refused first, naming ``param``."""
    shape = np.broadcast_shapes(*(np.shape(x) for x in (theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg)))
    count = int(np.prod(shape))
    temporaries = max(min(count, EVAL_CHUNK) * BYTES_PER_PAIR, min(count, FUSED_CHUNK) * FUSED_BYTES_PER_PAIR)
    cost.require_evaluations(brdf, count, count * len(want) * BYTES_PER_VALUE + temporaries, param,
                             f"{count} BRDF evaluations")
    if tuple(want) == ("f",) and getattr(brdf.fresnel, "channels", None) is None:
        f = _f_fused(brdf, shape, count, (theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg))
        if f is not None:
            return {"f": f}
    l = direction_deg(theta_i_deg, phi_i_deg)
    v = direction_deg(theta_o_deg, phi_o_deg)
    l, v = np.broadcast_arrays(l, v)

    def terms(l, v):
        if getattr(brdf.fresnel, "channels", None) is not None:   # a material: F_rgb, f_rgb too
            return evaluate_rgb(brdf, l, v, want)
        return {"f": kernels.f(brdf, l, v)} if tuple(want) == ("f",) else brdf.evaluate(l, v, want)
    if count <= EVAL_CHUNK:
        return terms(l, v)
    l, v = l.reshape(-1, 3), v.reshape(-1, 3)
    out: dict[str, np.ndarray] = {}
    for start in range(0, count, EVAL_CHUNK):
        if start:
            cost.check_deadline(f"{count} BRDF evaluations")
        part = slice(start, start + EVAL_CHUNK)
        for name, value in terms(l[part], v[part]).items():
            if name not in out:
                out[name] = np.empty((count,) + np.shape(value)[1:], dtype=np.result_type(value, float))
            out[name][part] = value
    return {name: value.reshape(shape + value.shape[1:]) for name, value in out.items()}


#: The precisions POST/GET /api/v1/eval take: float64 (the default, the reference path)
#: or float32 (f only, app/kernels/float32.py's loop, on explicit request).
PRECISIONS = ("float64", "float32")


def check_float32(brdf: BRDF, want, param: str = "precision", loc: str = "query") -> None:
    """Refuse (ParameterError naming ``param``: 422) a request precision=float32 does not
    serve: a quantity other than f, a coloured material, a model without a float32 loop
    (app/kernels/float32.py says which and why). Nothing is compiled or evaluated."""
    from .errors import ParameterError
    from .kernels import float32
    if tuple(want) != ("f",):
        raise ParameterError(param, "precision=float32 evaluates f only: ask quantities=f, "
                                    "or precision=float64 for the other quantities", loc=loc)
    if getattr(brdf.fresnel, "channels", None) is not None:
        raise ParameterError(param, "precision=float32 is not offered for a coloured material "
                                    "(f per channel): use precision=float64", loc=loc)
    why = float32.unsupported(brdf)
    if why is not None:
        raise ParameterError(param, f"precision=float32 is not available for this model: {why}; "
                                    "use precision=float64", loc=loc)


def evaluate_float32(brdf: BRDF, theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg, want,
                     param: str = "precision", loc: str = "query") -> dict:
    """f in float32 (app/kernels/float32.py: generated from the same formulas as float64,
    never the default) at direction pairs in degrees, in chunks of EVAL_CHUNK pairs, and
    ``precision``: the dtype and the stated bound on its relative error against float64
    over these pairs. A request float32 does not serve is refused first (check_float32)."""
    from .kernels import float32
    check_float32(brdf, want, param, loc)
    angles = (theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg)
    shape = np.broadcast_shapes(*(np.shape(x) for x in angles))
    count = int(np.prod(shape))
    cost.require_evaluations(brdf, count, count * BYTES_PER_VALUE + min(count, EVAL_CHUNK) * BYTES_PER_PAIR,
                             "n", f"{count} BRDF evaluations")
    flat = [np.broadcast_to(np.asarray(a, dtype=float), shape).reshape(-1) for a in angles]
    out = np.empty(count, dtype=np.float32)
    mu_sum_min = np.inf
    for start in range(0, count, EVAL_CHUNK):
        if start:
            cost.check_deadline(f"{count} BRDF evaluations")
        part = slice(start, start + EVAL_CHUNK)
        l = direction_deg(flat[0][part], flat[1][part])
        v = direction_deg(flat[2][part], flat[3][part])
        f = out[part] = float32.f(brdf, l, v)
        # the bound's pairs: f finite and nonzero (where f64 is 0 or ∞ so is f32)
        mu_sum = (np.maximum(l[..., 2], 0.0) + np.maximum(v[..., 2], 0.0))[np.isfinite(f) & (f != 0)]
        mu_sum_min = min(mu_sum_min, float(np.min(mu_sum, initial=np.inf)))
    alphas = [brdf.ndf] + ([brdf.lobe2] if brdf.lobe2 is not None and brdf.lobe_mix > 0 else [])
    bound = max(float(float32.rel_error_bound(n.alpha_x, n.alpha_y, mu_sum_min)) if np.isfinite(mu_sum_min)
                else 0.0 for n in alphas)
    return {"f": out.reshape(shape), "precision": {
        "dtype": "float32",
        "max_rel_error_bound": bound if np.isfinite(bound) else None,
        "bound": (f"|f32 - f64| <= {float32.REL_ERROR_K:.3g} / (alpha_min (mu_i + mu_o)) f64 per pair "
                  "(measured over GGX's float32 model classes, app/kernels/float32.py REL_ERROR_K); "
                  "max_rel_error_bound is its largest value over these pairs, null when a pair with "
                  "f not 0 has both directions on the horizon (no bound there)"),
        "reference": "float64 (the default precision)"}}


def _f_fused(brdf: BRDF, shape: tuple, count: int, angles: tuple) -> np.ndarray | None:
    """f by the model's compiled loop with degrees in (the directions built inside it),
    in chunks of FUSED_CHUNK pairs written straight into the result, the deadline
    checked between them; None when the model has no ready loop (the caller takes the
    directions path)."""
    if count <= FUSED_CHUNK:
        return kernels.f_deg(brdf, *angles)
    flat = [np.broadcast_to(np.asarray(a, dtype=float), shape).reshape(-1) for a in angles]
    out = np.empty(count)
    for start in range(0, count, FUSED_CHUNK):
        if start:
            cost.check_deadline(f"{count} BRDF evaluations")
        part = slice(start, start + FUSED_CHUNK)
        if kernels.f_deg(brdf, *(a[part] for a in flat), out=out[part]) is None:
            return None if not start else _finish_numpy(brdf, flat, out, start).reshape(shape)
    return out.reshape(shape)


def _finish_numpy(brdf: BRDF, flat: list, out: np.ndarray, start: int) -> np.ndarray:
    """The rest of a fused evaluation by numpy (the compiled loops were switched off
    between two chunks: kernels.disabled)."""
    l = direction_deg(flat[0][start:], flat[1][start:])
    v = direction_deg(flat[2][start:], flat[3][start:])
    out[start:] = kernels.f(brdf, l, v)
    return out


#: Pairs per call of the fused loop: 6-8 ms of work on two cores (141-170 M/s), so the deadline
#: is checked often. Each call hands its halves to the pool's threads, which cost ~0.3 ms
#: of wall time a call on this VM (waking a thread on an idle virtual CPU): at 2^18 pairs
#: the four calls of 10^6 pairs ran 10-20 % slower than one (/tmp script, 15 rounds).
FUSED_CHUNK = 1 << 20
#: a fused chunk's temporaries: its four angle arrays, copied where the inputs are not
#: contiguous (a broadcast grid), and a second lobe's f
FUSED_BYTES_PER_PAIR = 40


def _width_deg(brdf: BRDF) -> float:
    """The narrowest feature of the specular lobe, in degrees of the view direction:
    the half vector moves half as fast as v, and D falls off over θ_m ≈ α."""
    alphas = [brdf.ndf.alpha_x, brdf.ndf.alpha_y]
    if brdf.lobe2 is not None and brdf.lobe_mix > 0:
        alphas += [brdf.lobe2.alpha_x, brdf.lobe2.alpha_y]
    return float(np.rad2deg(2.0 * min(alphas)))


def _added(n: int) -> int:
    """Nodes refinement may add to a base of n: max(n, ADAPTIVE_MIN_ADDED)."""
    return max(n, ADAPTIVE_MIN_ADDED)


#: Refinement may always add this many nodes, so a coarse base still resolves a peak.
ADAPTIVE_MIN_ADDED = 256


def ndf_curve(brdf: BRDF, phi_deg: float, n: int, cosine: bool = False) -> dict:
    """D(θ_m) for θ_m = 0..90° (both ends) at azimuth φ; with ``cosine``, D·cos θ_m
    (the projected-area density: ∫ D cos θ_m dω_m = 1, Walter et al. 2007 eq. 4).

    ``n`` uniform angles plus nodes at θ_m = 0 on a ladder of α and where the drawn
    curve was off by more than adaptive.REFINE_TOL (at most max(n, 256) added); the
    response says how close (``resolution``) and gives the peak against its located
    maximum (``peak``)."""
    key = "D_cos" if cosine else "D"

    def value(theta):
        m = direction_deg(theta, phi_deg)
        D = brdf.ndf.D(m)
        return D * m[..., 2] if cosine else D

    seeds = np.concatenate([np.linspace(0.0, 90.0, n), ladder(0.0, _width_deg(brdf) / 2, 0.0, 90.0)])
    theta, D, report = refine_curve(value, seeds, max_added=_added(n))
    return {"theta_deg": theta, key: D, "peak": peak(D, report.pop("located"), key, "theta_deg"),
            "resolution": report}


def g1_curve(brdf: BRDF, phi_deg: float, n: int) -> dict:
    """Λ(θ_v) and G1(θ_v) = 1/(1+Λ) for θ_v = 0..90° at azimuth φ (Λ = +inf at 90°).

    ``n`` uniform angles plus nodes toward grazing on a ladder of α, refined where G1
    drawn was off by more than adaptive.REFINE_TOL (at most max(n, 256) added;
    ``resolution`` says how close). When the masking is not ``smith``, also G1_exact
    (the NDF's own Smith G1) and G1_error = G1 − G1_exact."""
    def value(theta):
        w = direction_deg(theta, phi_deg)
        return G1(w[..., 2], brdf.masking.mu_Lambda(brdf.ndf, w))

    seeds = np.concatenate([np.linspace(0.0, 90.0, n), ladder(90.0, _width_deg(brdf) / 2, 0.0, 90.0)])
    theta, g1, report = refine_curve(value, seeds, max_added=_added(n), locate=False)
    report.pop("located")
    w = direction_deg(theta, phi_deg)
    ml = brdf.masking.mu_Lambda(brdf.ndf, w)
    mu = w[..., 2]
    Lambda = np.divide(ml, mu, out=np.full_like(mu, np.inf), where=mu > 0)
    out = {"theta_deg": theta, "Lambda": Lambda, "G1": g1, "resolution": report}
    if brdf.masking.name != "smith":
        out["G1_exact"] = G1(mu, brdf.ndf.mu_Lambda(w))
        out["G1_error"] = out["G1"] - out["G1_exact"]
    return out


def lobe_curve(brdf: BRDF, theta_i_deg: float, phi_i_deg: float, n: int, cosine: bool) -> dict:
    """f in the plane of incidence, θ_o from −90° to 90°; θ_o > 0 on the mirror side
    (azimuth φ_i + 180°). ``cosine`` gives f·cos θ_o, the cosine of the varying
    direction: the outgoing density a sampler of v targets (it integrates to E).

    ``n`` uniform angles plus nodes at the mirror direction on a ladder of α, refined
    where the drawn curve was off by more than adaptive.REFINE_TOL of its peak (at most
    max(n, 256) added; ``resolution``); ``peak`` gives the largest value drawn against
    the located maximum and where it is."""
    def value(theta_o):
        phi_o = np.where(theta_o >= 0, phi_i_deg + 180.0, phi_i_deg)
        f = evaluate(brdf, theta_i_deg, phi_i_deg, np.abs(theta_o), phi_o, ("f",))["f"]
        if not cosine:
            return f
        mu_o = direction_deg(np.abs(theta_o), 0.0)[..., 2]
        # f·cos θ_o is 0 at θ_o = ±90° even where f diverges (both directions grazing)
        return where_valid(mu_o > 0.0, [f, mu_o], lambda a, b: a * b, 0.0)

    seeds = np.concatenate([np.linspace(-90.0, 90.0, n),
                            ladder(theta_i_deg, _width_deg(brdf), -90.0, 90.0)])
    theta_o, f, report = refine_curve(value, seeds, max_added=_added(n))
    key = "f_cos" if cosine else "f"
    return {"theta_o_deg": theta_o, key: f, "peak": peak(f, report.pop("located"), key, "theta_o_deg"),
            "resolution": report}


def lobe_grid(brdf: BRDF, theta_i_deg: float, phi_i_deg: float, n_theta: int, n_phi: int) -> dict:
    """f over the hemisphere of v: θ_v = 0..90° (n_theta), φ_v = 0..360° (n_phi), plus
    rows and columns at and around the mirror direction and where a cell was off the
    bilinear interpolation by more than adaptive.REFINE_TOL of the peak (at most
    max(n_theta, 64) rows and max(n_phi, 64) columns added; ``resolution``); ``peak``
    gives the largest value drawn against the located maximum."""
    def value(theta, phi):
        return evaluate(brdf, theta_i_deg, phi_i_deg, theta, phi, ("f",))["f"]

    width = _width_deg(brdf)
    phi_m = (phi_i_deg + 180.0) % 360.0
    sin_i = np.sin(np.deg2rad(theta_i_deg))
    phi_width = width / max(sin_i, np.deg2rad(width)) if theta_i_deg > 0 else 360.0
    theta = np.concatenate([np.linspace(0.0, 90.0, n_theta), ladder(theta_i_deg, width, 0.0, 90.0)])
    phi = np.concatenate([np.linspace(0.0, 360.0, n_phi)]
                         + [ladder(c, phi_width, 0.0, 360.0) for c in (phi_m - 360.0, phi_m, phi_m + 360.0)])
    theta, phi, f, report = refine_grid(value, theta, phi,
                                        max_added=(max(n_theta, 64), max(n_phi, 64)))
    return {"theta_deg": theta, "phi_deg": phi, "f": f,
            "peak": peak(f, report.pop("located"), "f", "theta_deg", "phi_deg"),
            "resolution": report}


def albedo_curve(brdf: BRDF, mu, phi_deg: float, tol: float, method: str = "quadrature",
                 order: int | None = None, samples: int = 1024, seed: int = 0) -> dict:
    """E(μ) at the given cosines and E_avg over [0, 1], with errors and cost, by
    ``method`` (integrate/methods.py; quadrature by default). With Kulla-Conty
    compensation E is single + multiple scattering and E_single is reported too.
    ``energy`` says whether E exceeds 1 beyond its errors (energy_check)."""
    data = albedo_by(brdf, mu, np.deg2rad(phi_deg), method, tol, order, samples, seed)
    data["energy"] = energy_check(data)
    return data


#: Standard errors a Monte Carlo E may lie above 1 before the model is said to create
#: energy (3σ: a false alarm at one μ in ~740).
ENERGY_MC_SIGMAS = 3.0


def energy_check(data: dict) -> dict:
    """Whether E(μ) exceeds 1 by more than every error term that applies: the method's
    (quadrature or table bound; ENERGY_MC_SIGMAS standard errors of Monte Carlo) and the
    Kulla-Conty compensation's own error. {"creates_energy", "excess" (max E − 1),
    "error" (the allowance at that μ)}."""
    E = np.asarray(data["E"], dtype=float)
    scale = ENERGY_MC_SIGMAS if str(data.get("method", "")).startswith("mc_") else 1.0
    allowance = scale * np.asarray(data["E_error"], dtype=float) + float(data.get("compensation_error", 0.0))
    k = int(np.argmax(E - allowance))
    return {"creates_energy": bool(E[k] - allowance[k] > 1.0), "excess": float(np.max(E) - 1.0),
            "error": float(allowance[k])}


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


#: Angle of incidence of the conventions' lobes (degrees) and their θ_o points.
CONVENTIONS_THETA_I_DEG = 45.0
CONVENTIONS_LOBE_POINTS = 361


def conventions_lobes(roughness: float, anisotropy: float) -> dict:
    """The ``conventions`` figure's arrays: each ecosystem's row (app/shader/conventions)
    with the GGX lobe f(θ_o) at its α (clipped to the evaluated range) in the plane of
    incidence, θ_o > 0 on the mirror side, F = 1; UE4's G rows with their Schlick-GGX k."""
    theta_o = np.linspace(-89.5, 89.5, CONVENTIONS_LOBE_POINTS)
    l = direction_deg(CONVENTIONS_THETA_I_DEG, 0.0)
    v = direction_deg(np.abs(theta_o), np.where(theta_o >= 0, 180.0, 0.0))
    rows = []
    for row in table(roughness, anisotropy):
        ax, ay = (float(np.clip(a, ALPHA_MIN, ALPHA_MAX)) for a in (row["alpha"], row["alpha_y"]))
        masking = "smith"
        if row["ecosystem"].startswith("UE4, G direct"):
            masking = "schlick_direct"
        elif row["ecosystem"].startswith("UE4, G image"):
            masking = "schlick_ibl"
        spec = make_spec(ndf="ggx", alpha=ax, alpha_y=None if ay == ax else ay, masking=masking, fresnel="none")
        f = spec.brdf().evaluate(np.broadcast_to(l, v.shape), v, ("f",))["f"]
        rows.append({**row, "theta_o_deg": theta_o, "f": f})
    return {"rows": rows, "theta_i_deg": CONVENTIONS_THETA_I_DEG, "alpha_range": (ALPHA_MIN, ALPHA_MAX)}


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
    l or v is below the horizon (no such pair of directions exists).

    ``n`` uniform angles per axis plus columns at θ_h = 0 on a ladder of α (the
    highlight) and where the row θ_d = SLICE_PROBE_THETA_D drawn was off by more than
    adaptive.REFINE_TOL of its peak (at most max(n, 256) added; ``resolution``);
    ``peak`` gives that row's largest value drawn against its located maximum."""
    def value(theta_d, theta_h):
        l, v = rusinkiewicz_directions(theta_h, phi_h_deg, theta_d, phi_d_deg)
        l, v = np.broadcast_arrays(l, v)
        above = (l[..., 2] >= 0.0) & (v[..., 2] >= 0.0)
        f = np.full(above.shape, np.nan)
        if above.any():
            out = kernels.f(brdf, l[above], v[above])
            if cosine:
                # f·cos θ_l is 0 at θ_l = 90° even where f diverges (both directions grazing)
                mu_l = l[above][:, 2]
                out = where_valid(mu_l > 0.0, [out, mu_l], lambda a, b: a * b, 0.0)
            f[above] = out
        return f

    theta = np.linspace(0.0, 90.0, n)
    seeds = np.concatenate([theta, ladder(0.0, _width_deg(brdf) / 2, 0.0, 90.0)])
    # no peak search: at φ_d = 90° the column θ_h = 90° is a divergence (both directions
    # graze), which a search would chase to a node 1e-11° from it (f ~ 1e13)
    theta_h, probe, report = refine_curve(lambda t: value(SLICE_PROBE_THETA_D, t), seeds,
                                          max_added=_added(n), locate=False)
    report["located"] = _largest(theta_h, probe)
    f = value(theta[:, None], theta_h[None, :])
    key = "f_cos" if cosine else "f"
    return {"theta_d_deg": theta, "theta_h_deg": theta_h, key: f,
            "peak": {**peak(probe, report.pop("located"), key, "theta_h_deg"),
                     "theta_d_deg": SLICE_PROBE_THETA_D},
            "resolution": report}


def _largest(x, y):
    """(x, y) of the largest finite y: the drawn maximum, as the located one."""
    finite = np.isfinite(y)
    if not finite.any():
        return None
    k = int(np.argmax(np.where(finite, y, -np.inf)))
    return float(x[k]), float(y[k])


#: The row of the slice on which the highlight's columns are refined: the highlight
#: (D around θ_h = 0) has the same width in every row; rows toward θ_d = 90° also carry
#: the divergence of f where both directions graze, which no grid resolves.
SLICE_PROBE_THETA_D = 30.0


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
