"""A data set on a view's own axes: the data at the nodes where the view drew the model,
model − data there, and the largest relative error with where it is.

One function per view, each given the data set, the model, the model's arrays (as the
view computed them) and the view's query. MERL tables are looked up at the very same
nodes, interpolated linearly between cell centres (merl.lookup_linear: the reader's
nearest cell would show the format's 1° steps as errors of ~7 % on a GGX α = 0.2 lobe,
linear interpolation ~0.05 % typical); scattered samples are shown where
they were taken (the lobe: those in the plane of incidence at the view's θ_i), with the
model evaluated there. Where the data hold nothing the value is NaN: a gap when drawn,
null in JSON.
"""
from __future__ import annotations

import numpy as np

from ..environment.sphere import frames_at
from ..errors import ParameterError
from ..physics.numeric import where_valid
from ..physics.vectors import direction_deg
from ..quantities import albedo_curve, evaluate, rusinkiewicz_directions
from . import merl
from .dataset import angles_deg, select, term_of_model

#: samples count as "at" the view's incidence, and "in" its plane, within this angle: a
#: CSV written in whole or half degrees is matched, neighbouring rows of a 1° grid are not
MATCH_DEG = 0.25
#: tolerance of the model's E(μ) at the data's μ (the data's own error bars are ~1e-3)
ALBEDO_TOL = 1e-6


class MeasuredBRDF:
    """A MERL table in the place of a model: ``evaluate`` interpolates f (NaN where not
    measured)."""

    def __init__(self, data, channel: str | None):
        self.data, self.channel = data, channel

    def evaluate(self, l, v, want=("f",)) -> dict:
        values = merl.lookup_linear(self.data.table, l, v)
        f = select(values, self.data.channels, self.channel)
        return {"f": np.where((values >= 0).all(axis=0), f, np.nan)}

    def at_deg(self, theta_i_deg, phi_i_deg, theta_o_deg, phi_o_deg) -> np.ndarray:
        """f at direction pairs given in degrees, broadcast together."""
        l, v = np.broadcast_arrays(direction_deg(theta_i_deg, phi_i_deg),
                                   direction_deg(theta_o_deg, phi_o_deg))
        return self.evaluate(l, v)["f"]


def _stats(model, data, axes: dict) -> dict:
    """model − data and (data − model)/model where both exist and the model is positive."""
    model, data = np.asarray(model, dtype=float), np.asarray(data, dtype=float)
    ok = np.isfinite(data) & np.isfinite(model) & (model > 0)
    relative = where_valid(ok, [data, model], lambda d, m: (d - m) / m, np.nan)
    out = {"difference": np.where(ok, model - data, np.nan), "relative_error": relative,
           "compared": int(ok.sum()), "max_relative_error": None, "where": None}
    if ok.any():
        k = np.unravel_index(int(np.nanargmax(np.abs(relative))), relative.shape)
        out["max_relative_error"] = float(relative[k])
        out["where"] = {name: float(np.broadcast_to(x, relative.shape)[k]) for name, x in axes.items()}
    return out


def _table(data, view: str) -> None:
    if data.kind != "brdf" or data.table is None:
        raise ParameterError("data", f"the {view} view overlays a MERL table (scattered samples "
                                     f"are compared at their points by /difference); this data "
                                     f"set is {data.format}")


def _result(key, axes, values, model, note, grid_axes=None) -> dict:
    return {"key": key, "axes": axes, "data": values, "model": np.asarray(model, dtype=float),
            "note": note, **_stats(model, values, grid_axes or axes)}


def lobe(data, brdf, arrays: dict, q, channel) -> dict:
    key = "f_cos" if "f_cos" in arrays else "f"
    if data.kind != "brdf":
        raise ParameterError("data", f"the lobe view overlays BRDF data; this is {data.format}")
    if data.table is not None:
        theta_o = np.asarray(arrays["theta_o_deg"])
        source, model = MeasuredBRDF(data, channel), arrays[key]
        note = "the table interpolated at the view's nodes"
    else:
        (ti, pi), (to, po) = angles_deg(data.l), angles_deg(data.v)
        dphi = np.mod(po - pi + 180.0, 360.0) - 180.0            # φ_o − φ_i in [−180, 180)
        at = np.abs(ti - q.theta_i_deg) <= MATCH_DEG
        mirror = at & (np.abs(np.abs(dphi) - 180.0) <= MATCH_DEG)
        keep = mirror | (at & (np.abs(dphi) <= MATCH_DEG))
        theta_o = np.where(mirror, to, -to)[keep]
        order = np.argsort(theta_o, kind="stable")
        theta_o, source = theta_o[order], None
        sampled = select(data.f[:, keep], data.channels, channel)[order]
        note = (f"{theta_o.size} samples in the plane of incidence at θ_i = {q.theta_i_deg:g}° "
                f"(within {MATCH_DEG:g}°)")
    phi_o = np.where(theta_o >= 0, q.phi_i_deg + 180.0, q.phi_i_deg)
    if source is None:
        model = evaluate(brdf, q.theta_i_deg, q.phi_i_deg, np.abs(theta_o), phi_o, ("f",))["f"]
        values = sampled
    else:
        values = source.at_deg(q.theta_i_deg, q.phi_i_deg, np.abs(theta_o), phi_o)
    if key == "f_cos":
        mu_o = direction_deg(np.abs(theta_o), 0.0)[..., 2]
        values = values * mu_o
        if source is None:
            model = model * mu_o
    return _result(key, {"theta_o_deg": theta_o}, values, model, note)


def lobe3d(data, brdf, arrays: dict, q, channel) -> dict:
    _table(data, "lobe3d")
    theta, phi = np.asarray(arrays["theta_deg"]), np.asarray(arrays["phi_deg"])
    values = MeasuredBRDF(data, channel).at_deg(q.theta_i_deg, q.phi_i_deg, theta[:, None],
                                                phi[None, :])
    return _result("f", {"theta_deg": theta, "phi_deg": phi}, values, arrays["f"],
                   "the table interpolated at the view's nodes",
                   {"theta_deg": theta[:, None], "phi_deg": phi[None, :]})


def half_difference(data, brdf, arrays: dict, q, channel) -> dict:
    _table(data, "slice")
    key = "f_cos" if "f_cos" in arrays else "f"
    theta_h, theta_d = np.asarray(arrays["theta_h_deg"]), np.asarray(arrays["theta_d_deg"])
    l, v = rusinkiewicz_directions(theta_h[None, :], q.phi_h_deg, theta_d[:, None], q.phi_d_deg)
    l, v = np.broadcast_arrays(l, v)
    above = (l[..., 2] >= 0.0) & (v[..., 2] >= 0.0)
    values = np.full(above.shape, np.nan)
    values[above] = MeasuredBRDF(data, channel).evaluate(l[above], v[above])["f"]
    if key == "f_cos":
        values = values * np.maximum(l[..., 2], 0.0)
    return _result(key, {"theta_d_deg": theta_d, "theta_h_deg": theta_h}, values, arrays[key],
                   "the table interpolated at the view's nodes",
                   {"theta_d_deg": theta_d[:, None], "theta_h_deg": theta_h[None, :]})


def _sphere_frames(x, y, light):
    """(l, v, n·l) in the local frames of the sphere's pixels (the view along +z), in the
    one pixel frame of the lit sphere (environment.sphere.frames_at), for data, which the
    compiled kernels behind the sphere renderer cannot evaluate."""
    frame = frames_at(x, y)
    l, v = frame @ light, frame @ np.array([0.0, 0.0, 1.0])
    return l, v, l[:, 2]


def sphere(data, brdf, arrays: dict, q, channel) -> dict:
    """L_o/E of the data at the pixel centres (the model's pixels round the highlight are
    means over sub-pixels; the table's 1° cells are coarser than those anyway)."""
    _table(data, "sphere")
    x, y = np.asarray(arrays["x"]), np.asarray(arrays["y"])
    X, Y = np.meshgrid(x, y)                       # rows y, columns x, as the view's
    on = X * X + Y * Y < 1.0
    l, v, mu_l = _sphere_frames(X[on], Y[on], direction_deg(q.theta_i_deg, q.phi_i_deg))
    lit = np.zeros(mu_l.shape)
    lit[mu_l > 0] = MeasuredBRDF(data, channel).evaluate(l[mu_l > 0], v[mu_l > 0])["f"] * mu_l[mu_l > 0]
    values = np.full(X.shape, np.nan)
    values[on] = lit
    return _result("radiance", {"y": y, "x": x}, values, arrays["radiance"],
                   "the table interpolated at each pixel centre's (l, v)",
                   {"y": y[:, None], "x": x[None, :]})


def albedo(data, brdf, arrays: dict, q, channel, summary: dict) -> dict:
    if data.kind == "term":
        if data.axis != "mu":
            raise ParameterError("data", "the albedo view overlays E(μ) or BRDF data; this data "
                                         f"set holds {', '.join(data.terms)} against θ")
        mu, values, errors = data.x, data.terms["E"], None
        note = "E(μ) as given"
    else:
        found = summary["albedo"]
        mu = np.asarray(found["mu"], dtype=float)
        name = channel if channel in found["E"] else None
        if name is None:
            stacked = np.array([found["E"][c] for c in data.channels]).reshape(len(data.channels), -1)
            errs = np.array([found["E_error"][c] for c in data.channels]).reshape(len(data.channels), -1)
            values, errors = select(stacked, data.channels, channel), select(errs, data.channels, channel)
        else:
            values, errors = np.asarray(found["E"][name]), np.asarray(found["E_error"][name])
        note = found["method"]
    model = (albedo_curve(brdf, mu, q.phi_deg if hasattr(q, "phi_deg") else 0.0, ALBEDO_TOL)["E"]
             if mu.size else np.empty(0))
    out = _result("E", {"mu": mu}, np.asarray(values, dtype=float), model, note)
    out["data_error"] = errors
    return out


def term(name: str):
    """The overlay of a term view (ndf → D, g1 → G1, fresnel → F) on term data."""
    view = {"D": "ndf", "G1": "g1", "F": "fresnel"}[name]

    def overlay(data, brdf, arrays: dict, q, channel) -> dict:
        if data.kind != "term" or name not in data.terms:
            held = ", ".join(data.terms) if data.kind == "term" else "BRDF values"
            raise ParameterError("data", f"the {view} view overlays a term CSV with {name}; this "
                                         f"data set holds {held}")
        theta = data.x
        values, model = data.terms[name], term_of_model(brdf, name, theta)
        key = name
        if name == "D" and "D_cos" in arrays:
            mu = direction_deg(theta, 0.0)[..., 2]
            values, model, key = values * mu, model * mu, "D_cos"
        return _result(key, {"theta_deg": theta}, values, model, f"all {theta.size} rows of {name}")
    return overlay


#: view name → its overlay
OVERLAYS = {"lobe": lobe, "lobe3d": lobe3d, "slice": half_difference, "sphere": sphere,
            "albedo": albedo, "ndf": term("D"), "g1": term("G1"), "fresnel": term("F")}
