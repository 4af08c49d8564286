"""The shapes at which an NDF's Smith integral is tested: each shape parameter at its
lower end (just inside it when the end is open: ×1.017) and at its upper end, the
others at their defaults; an NDF without shape parameters once."""
from __future__ import annotations


def shape_extremes(cls) -> list[dict]:
    if not cls.shape_params:
        return [{}]
    return ([{p.name: (p.lo * 1.017 if p.lo_open else p.lo)} for p in cls.shape_params]
            + [{p.name: p.hi} for p in cls.shape_params])
