"""A data set as the rest of the app sees it: measured BRDF values at direction pairs
(a MERL table or scattered samples) or one term against its angle.

``points`` gives the measured values with their directions (what a fit and an overlay
compare a model with); ``select`` picks a channel.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

from ..errors import ParameterError
from ..physics.masking import G1
from ..physics.vectors import direction_deg
from ..quantities import rusinkiewicz_directions
from . import merl

#: Rec. 709 / sRGB luminance weights of linear R, G, B (ITU-R BT.709)
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])


def angles_deg(w: np.ndarray):
    """(θ, φ) in degrees of directions (..., 3); φ in [0°, 360°)."""
    theta = np.rad2deg(np.arccos(np.clip(w[..., 2], -1.0, 1.0)))
    return theta, np.mod(np.rad2deg(np.arctan2(w[..., 1], w[..., 0])), 360.0)


def term_of_model(brdf, term: str, theta_deg: np.ndarray) -> np.ndarray:
    """D, G1 or F of a model against θ (degrees, azimuth 0): what a term CSV holds."""
    w = direction_deg(theta_deg, 0.0)
    if term == "D":
        return brdf.ndf.D(w)
    if term == "G1":
        return G1(w[..., 2], brdf.masking.mu_Lambda(brdf.ndf, w))
    return brdf.fresnel.F(w[..., 2])


def select(values: np.ndarray, channels: tuple[str, ...], channel: str | None) -> np.ndarray:
    """values[channel, ...] → the requested channel's values. RGB data: r, g, b or
    luminance (default); one-channel data: that channel (any name but r/g/b)."""
    if channels == ("r", "g", "b"):
        if channel in (None, "luminance"):
            return np.tensordot(LUMINANCE, values, axes=1)
        if channel in channels:
            return values[channels.index(channel)]
        raise ParameterError("channel", f"channel must be one of r, g, b, luminance; got {channel!r}")
    if channel in (None, "luminance", channels[0]):
        return values[0]
    raise ParameterError("channel", f"this data set has one channel ({channels[0]}): give "
                                    f"channel=luminance or leave it out; got {channel!r}")


@dataclass(frozen=True, eq=False)
class BrdfData:
    """f in 1/sr at direction pairs: a MERL table (``table``) or samples (``l``, ``v``,
    ``f[channel, n]``)."""
    format: str
    channels: tuple[str, ...]
    size: int
    table: np.ndarray | None = None
    l: np.ndarray | None = None
    v: np.ndarray | None = None
    f: np.ndarray | None = None
    kind = "brdf"

    @property
    def nbytes(self) -> int:
        return sum(a.nbytes for a in (self.table, self.l, self.v, self.f) if a is not None)

    @property
    def count(self) -> int:
        return self.table[0].size if self.table is not None else self.f.shape[1]

    def measured(self) -> np.ndarray:
        """Which cells/samples hold a value in every channel."""
        values = self.table.reshape(len(self.channels), -1) if self.table is not None else self.f
        return (values >= 0).all(axis=0)

    def points(self, channel: str | None, limit: int | None = None, seed: int = 0):
        """(l, v, f, note): measured direction pairs and values of one channel; at most
        ``limit`` of them, a fixed-seed random subset (the same for every call), which
        ``note`` describes."""
        index = np.flatnonzero(self.measured())
        note = f"all {index.size} measured {'cells' if self.table is not None else 'samples'}"
        if limit is not None and index.size > limit:
            index = np.sort(np.random.default_rng(seed).choice(index, limit, replace=False))
            note = (f"{limit} of {self.count} {'cells' if self.table is not None else 'samples'}"
                    f" (a fixed-seed random subset, seed {seed}, of the measured ones)")
        if self.table is not None:
            i, j, k = np.unravel_index(index, merl.DIMS)
            theta_h, theta_d, phi_d = merl.centres_deg()
            l, v = rusinkiewicz_directions(theta_h[i], 0.0, theta_d[j], phi_d[k])
            values = self.table.reshape(len(self.channels), -1)[:, index]
        else:
            l, v, values = self.l[index], self.v[index], self.f[:, index]
        return l, v, select(values, self.channels, channel), note


@dataclass(frozen=True, eq=False)
class TermData:
    """One or more of D, G1, F against θ (degrees), or E against μ."""
    format: str
    axis: str
    x: np.ndarray
    terms: dict
    size: int
    kind = "term"

    @property
    def channels(self) -> tuple[str, ...]:
        return tuple(self.terms)

    @property
    def nbytes(self) -> int:
        return self.x.nbytes + sum(a.nbytes for a in self.terms.values())

    @property
    def count(self) -> int:
        return self.x.size


def samples_data(angles: dict, channels: tuple[str, ...], f: np.ndarray, size: int) -> BrdfData:
    l = direction_deg(angles["theta_i_deg"], angles["phi_i_deg"])
    v = direction_deg(angles["theta_o_deg"], angles["phi_o_deg"])
    return BrdfData("samples_csv", channels, size, l=l, v=v, f=f)
