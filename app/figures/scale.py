"""Colour (and radius) ranges an image cannot hide behind.

An image's colour scale is set by the finite values that cover its area, not by its
largest one: a divergence (f → ∞ where both directions graze) or a spike narrower than a
pixel would otherwise stretch the scale until every value of interest is one colour.
The top of the scale is the COLOUR_QUANTILE quantile of the finite values weighted by the
area each cell covers; what lies above is drawn in the top colour and the share of the
area it covers is stated in the colour bar's title. Non-finite values never enter.
"""
from __future__ import annotations

from dataclasses import dataclass

import numpy as np

#: The share of an image's area at or below the top of its colour scale. A feature
#: covering less than 1 − COLOUR_QUANTILE = 1 % of the area cannot set the scale
#: (a grazing divergence column, a sub-pixel clearcoat glint); one covering more does.
COLOUR_QUANTILE = 0.999


@dataclass(frozen=True)
class ColourRange:
    """``top``: the scale's top; ``clipped``: the share of the finite area above it;
    ``largest``: the largest finite value (None when nothing is finite)."""
    top: float | None
    clipped: float
    largest: float | None

    def note(self) -> str:
        """What the colour bar's title adds: nothing when nothing is clipped."""
        if self.top is None or self.clipped <= 0.0:
            return ""
        # one line: each line of a colour bar's title shortens the bar (six decade labels
        # overlapped on a bar squashed under three lines in half a page)
        return (f"top: {100 * COLOUR_QUANTILE:g}th pct of area, "
                f"{100 * self.clipped:.2g} % above (max {self.largest:.3g})")


def cell_widths(centres) -> np.ndarray:
    """The extent of each node of a (possibly refined, non-uniform) axis: half the gap to
    each neighbour (the midpoint rule's weights). One node alone weighs 1."""
    c = np.asarray(centres, dtype=float)
    if c.size < 2:
        return np.ones(c.shape)
    edges = np.concatenate([c[:1], (c[1:] + c[:-1]) / 2.0, c[-1:]])
    return np.abs(np.diff(edges))


def grid_weights(rows, columns) -> np.ndarray:
    """Area weights of a rows × columns image on (possibly non-uniform) axes."""
    return cell_widths(rows)[:, None] * cell_widths(columns)[None, :]


def colour_range(values, weights=None) -> ColourRange:
    """The top of a colour scale for ``values`` (any shape; ``weights`` broadcast to it,
    default uniform): the weighted COLOUR_QUANTILE quantile of the finite values."""
    v = np.asarray(values, dtype=float)
    w = np.broadcast_to(np.ones(()) if weights is None else np.asarray(weights, dtype=float), v.shape)
    finite = np.isfinite(v)
    if not finite.any():
        return ColourRange(None, 0.0, None)
    v, w = v[finite], w[finite]
    largest = float(v.max())
    total = float(w.sum())
    if total <= 0.0:
        return ColourRange(largest, 0.0, largest)
    order = np.argsort(v, kind="stable")
    cumulative = np.cumsum(w[order]) / total
    top = float(v[order][min(np.searchsorted(cumulative, COLOUR_QUANTILE), v.size - 1)])
    clipped = float(w[v > top].sum() / total)
    return ColourRange(top, clipped, largest)


def titled(text: str, scale: ColourRange) -> str:
    """A colour bar title with the clipping note on its own line."""
    note = scale.note()
    return f"{text}<br><sub>{note}</sub>" if note else text
