"""A model parameter declared next to the formula that uses it.

The registry publishes these (``GET /api/v1/models``); the API validates against them and
the page builds its sliders from them, so a new model declares its parameters once.
"""
from __future__ import annotations

from dataclasses import asdict, dataclass


@dataclass(frozen=True)
class Param:
    name: str            # the API / URL name, e.g. "alpha"
    label: str           # what the page shows, e.g. "α (roughness)"
    lo: float            # allowed range, inclusive unless lo_open
    hi: float
    default: float
    description: str
    lo_open: bool = False
    scale: str = "linear"  # "linear" or "log": how a slider should map it
    unit: str = ""

    def as_dict(self) -> dict:
        return asdict(self)

    def contains(self, x: float) -> bool:
        above = x > self.lo if self.lo_open else x >= self.lo
        return above and x <= self.hi

    def range_text(self) -> str:
        return f"{'(' if self.lo_open else '['}{self.lo:g}, {self.hi:g}]"
