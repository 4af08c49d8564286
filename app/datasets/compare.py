"""Model against data: the difference model − data at the data's own points, and its
largest relative error with where it is — what tells a shader's dump it is wrong, and
where to look."""
from __future__ import annotations

import numpy as np

from ..physics.numeric import where_valid
from .channel import model_f
from .dataset import TermData, angles_deg, term_of_model


def difference(data, brdf, channel: str | None, limit: int | None = None) -> dict:
    """model − data at the data's points; the relative error (data − model)/model where
    the model is positive, its largest magnitude and the point where it is. At most
    ``limit`` points (a fixed-seed random subset, as for BRDF data); a coloured model is
    compared in the data's channel."""
    if isinstance(data, TermData):
        term = channel if channel in data.terms else next(iter(data.terms))
        index = np.arange(data.count)
        note = f"all {data.count} rows of {term}"
        if limit is not None and data.count > limit:
            index = np.sort(np.random.default_rng(0).choice(data.count, limit, replace=False))
            note = f"{limit} of {data.count} rows of {term} (a fixed-seed random subset, seed 0)"
        x = data.x[index]
        model = term_of_model(brdf, term, x) if data.axis == "theta_deg" else None
        target, where = data.terms[term][index], {data.axis: x}
    else:
        l, v, target, note = data.points(channel, limit)
        model = model_f(brdf, l, v, channel)
        (ti, pi), (to, po) = angles_deg(l), angles_deg(v)
        where = {"theta_i_deg": ti, "phi_i_deg": pi, "theta_o_deg": to, "phi_o_deg": po}
    if model is None:
        return {"available": False, "note": "E(μ) data: compare it with the albedo view"}
    ok = np.isfinite(model) & (model > 0)
    relative = where_valid(ok, [target, model], lambda d, m: (d - m) / m, 0.0)
    k = int(np.argmax(np.abs(relative))) if ok.any() else 0
    return {"available": True, "points": int(target.size), "note": note,
            "model": model, "data": target, "difference": model - target,
            "relative_error": relative, "at": where,
            "max_relative_error": float(relative[k]),
            "where": {name: float(x[k]) for name, x in where.items()},
            "rms_relative_error": float(np.sqrt(np.mean(relative[ok] ** 2))) if ok.any() else None}
