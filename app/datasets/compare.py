"""Model against data: the difference model − data at the data's own points, and its
largest relative error with where it is — what tells a shader's dump it is wrong, and
where to look."""
from __future__ import annotations

import numpy as np

from ..physics.numeric import where_valid
from .channel import model_f
from .dataset import TermData, angles_deg, term_of_model


#: The relative error (data − model)/model is stated where the model is positive and it is a
#: float: data − model does not overflow (data ≥ model − FLOAT_MAX) and |data − model|/model
#: is at most HALF_MAX (half the largest float: margin for the division's rounding).
#: Elsewhere — a model of 0 against any data, data of 10³⁰⁸ against a model of 10⁻¹⁰ — it is
#: undefined: a gap (null in JSON), left out of the largest and the rms. (A model of 0 once
#: read as a relative error of 0: a perfect match for data of 1.7e308.)
FLOAT_MAX = np.finfo(float).max
HALF_MAX = FLOAT_MAX / 2


def difference(data, brdf, channel: str | None, limit: int | None = None) -> dict:
    """model − data at the data's points; the relative error (data − model)/model where
    it is defined (HALF_MAX), its largest magnitude and the point where it is. At most
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
    ok = np.isfinite(model) & (model > 0) & np.isfinite(target)
    ok = where_valid(ok, [target, model], lambda d, m: d >= m - FLOAT_MAX, 0.0) > 0   # d − m a float
    ok = where_valid(ok, [target, model], lambda d, m: np.abs(d - m) / HALF_MAX <= m, 0.0) > 0
    relative = where_valid(ok, [target, model], lambda d, m: (d - m) / m, np.nan)   # NaN: a gap
    k = int(np.argmax(np.where(ok, np.abs(relative), -1.0)))
    largest = abs(relative[k]) if ok.any() else None   # the rms scaled by it: no overflow
    rms = None if largest is None else (
        largest * float(np.sqrt(np.mean((relative[ok] / largest) ** 2))) if largest > 0 else 0.0)
    return {"available": True, "points": int(target.size), "note": note,
            "model": model, "data": target, "difference": model - target,
            "relative_error": relative, "at": where,
            "max_relative_error": None if largest is None else float(relative[k]),
            "where": None if largest is None else {name: float(x[k]) for name, x in where.items()},
            "rms_relative_error": rms}
