"""Shared look of every figure: colour-blind-safe palette, fonts, margins."""
from __future__ import annotations

import numpy as np

from .titles import model_title  # noqa: F401  (every builder's title names the model)

# Okabe & Ito 2008, "Color Universal Design": distinguishable by colour-blind readers.
PALETTE = ["#0072B2", "#D55E00", "#009E73", "#CC79A7", "#E69F00", "#56B4E9", "#000000"]
DIRECTION_COLORS = {"normal": "#555555", "incident": "#E69F00", "mirror": "#009E73"}


def base_layout(title: str, **extra) -> dict:
    layout = {
        "title": {"text": title, "x": 0.02, "xanchor": "left", "font": {"size": 15}},
        "font": {"family": "Inter, Segoe UI, Helvetica, Arial, sans-serif", "size": 12},
        "margin": {"l": 60, "r": 20, "t": 46, "b": 50},
        "paper_bgcolor": "white",
        "plot_bgcolor": "white",
        "colorway": PALETTE,
        "legend": {"orientation": "h", "y": -0.18, "x": 0},
        "hovermode": "closest",
    }
    layout.update(extra)
    return layout


def axis(title: str, **extra) -> dict:
    out = {"title": {"text": title}, "showgrid": True, "gridcolor": "#e5e5e5",
           "zeroline": False, "linecolor": "#888", "ticks": "outside"}
    out.update(extra)
    return out


def gaps(values) -> np.ndarray:
    """Values for plotting: a divergence (+inf) becomes a gap (NaN is Plotly's gap)."""
    v = np.asarray(values, dtype=float)
    return np.where(np.isfinite(v), v, np.nan)


def log_axis(title: str, values, decades: float, **extra) -> dict:
    """A log axis spanning at most ``decades`` below the largest finite positive value (a
    Beckmann tail underflows to 1e-300; nobody wants to see that), at least one decade
    either side of a constant curve, and labelled ticks enough to read it: every digit
    within 1.5 decades, 1-2-5 within LOG_TICKS_125_DECADES, one a decade beyond."""
    v = np.asarray(values, dtype=float)
    v = v[np.isfinite(v) & (v > 0)]
    out = axis(title, type="log", dtick=1, exponentformat="power", **extra)
    if v.size:
        hi, lo = np.log10(v.max()), np.log10(v.min())
        if hi - lo < 1.0:
            lo, hi = lo - 1.0, hi + 1.0
        out["range"] = [max(lo, hi - decades), hi + 0.15]
        out["dtick"] = log_dtick(out["range"][1] - out["range"][0])
    return out


#: Up to this many decades a log axis labels 2 and 5 between the powers of ten.
LOG_TICKS_125_DECADES = 3.5


def log_dtick(span_decades: float):
    """Plotly's log-axis tick rule for a span: "D1" labels every digit, "D2" 2 and 5,
    n a power of ten every n decades (about 4-12 labels on any span)."""
    if span_decades <= 1.5:
        return "D1"
    if span_decades <= LOG_TICKS_125_DECADES:
        return "D2"
    return max(1, int(np.ceil(span_decades / 10)))
