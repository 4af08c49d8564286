"""Several figures of one view, one per value of a varied parameter, drawn as one:
GGX against Beckmann at the same α, E(μ) across roughness.

Works on the figure dicts alone (no physics): the curves of each figure are recoloured
by value (one colour per value, the palette's order) and labelled with it; traces a
builder marks ``meta.role = "guide"`` (directions, outlines) are drawn once. Images and
surfaces cannot be overlaid and are refused.
"""
from __future__ import annotations

import copy

from ..errors import ParameterError
from .markup import subscripted
from .style import PALETTE, log_dtick

OVERLAY_TRACES = {"scatter", "scatterpolar"}
# Dash patterns that tell apart the curves of one figure (G1 and Λ) once colour is
# taken by the varied value.
DASHES = ["solid", "dash", "dot", "dashdot"]
# Opacity of a recoloured error band or fill.
FILL_ALPHA = 0.15


def is_guide(trace: dict) -> bool:
    meta = trace.get("meta")
    return isinstance(meta, dict) and meta.get("role") == "guide"


def overlayable(figure: dict) -> bool:
    return all(t.get("type", "scatter") in OVERLAY_TRACES or is_guide(t) for t in figure["data"])


def _rgba(hex_colour: str, alpha: float) -> str:
    r, g, b = (int(hex_colour[i:i + 2], 16) for i in (1, 3, 5))
    return f"rgba({r},{g},{b},{alpha})"


def _merge_ranges(layouts: list[dict], path: tuple[str, ...]) -> None:
    """Widen an explicit axis range of the first layout to cover every figure's."""
    ranges = []
    for layout in layouts:
        node = layout
        for key in path:
            node = node.get(key) if isinstance(node, dict) else None
        if isinstance(node, dict) and isinstance(node.get("range"), list):
            ranges.append(node["range"])
    if len(ranges) == len(layouts) and ranges:
        target = layouts[0]
        for key in path:
            target = target[key]
        target["range"] = [min(r[0] for r in ranges), max(r[1] for r in ranges)]
        # a log axis's tick spacing is chosen for its span (style.log_dtick): the union of
        # NDF tails over ten decades labelled every 2 and 5 of each decade crammed 30 labels
        if target.get("type") == "log" and "dtick" in target:
            target["dtick"] = log_dtick(target["range"][1] - target["range"][0])


def comparison_title(figures: list[dict], labels: list[str]) -> str:
    """A heading for the compared curves: what the first figure shows (its title up to
    " — ") and the labels, "f(l, v) in the plane of incidence — GGX α=0.2 vs Beckmann α=0.2"."""
    title = figures[0].get("layout", {}).get("title") or {}
    text = title.get("text", "") if isinstance(title, dict) else str(title)
    head = text.split(" — ")[0].split("<br>")[0]
    return f"{head} — {' vs '.join(labels)}" if head else " vs ".join(labels)


def shared_description(figures: list[dict]) -> str:
    """What the compared figures' titles say alike after " — " (the model, its varied
    value left out): "GGX α=0.1 · F Gold" and "GGX α=0.4 · F Gold" give "GGX · F Gold".
    Word by word where the titles have as many words, else the words they begin with."""
    tails = []
    for figure in figures:
        title = figure.get("layout", {}).get("title") or {}
        text = (title.get("text", "") if isinstance(title, dict) else str(title)).split("<br>")[0]
        tails.append(text.split(" — ", 1)[1].split() if " — " in text else [])
    if len({len(t) for t in tails}) == 1:
        kept = [words[0] for words in zip(*tails) if len(set(words)) == 1]
    else:
        kept = []
        for words in zip(*tails):
            if len(set(words)) > 1:
                break
            kept.append(words[0])
    out = []
    for word in kept:           # no separator doubled, none at either end
        if word == "·" and (not out or out[-1] == "·"):
            continue
        out.append(word)
    while out and out[-1] == "·":
        out.pop()
    return " ".join(out).rstrip(",")


#: A comparison of a model's colour channels draws each in its own hue, not the palette's
#: k-th colour (which drew the red channel blue): Paul Tol's "bright" red, green, blue.
CHANNEL_COLOURS = {"channel=r": "#EE6677", "channel=g": "#228833", "channel=b": "#4477AA"}


@subscripted
def overlay(figures: list[dict], labels: list[str], title: str | None = None,
            param: str = "vary") -> dict:
    """One figure with the curves of ``figures`` (label k belongs to figure k), headed
    ``title`` or, by default, :func:`comparison_title`. Figures that are not curves are
    refused with a ParameterError naming ``param`` (the request's parameter that asked
    for the overlay)."""
    if not figures or len(figures) != len(labels):
        raise ValueError("one label per figure")
    for fig in figures:
        if not overlayable(fig):
            kinds = sorted({t.get("type", "") for t in fig["data"]} - OVERLAY_TRACES)
            raise ParameterError(param, f"{param}: this figure has {', '.join(kinds)} traces, "
                                        "which cannot be overlaid (only curve figures can)")
    traces = []
    for k, (fig, label) in enumerate(zip(figures, labels)):
        colour = CHANNEL_COLOURS.get(label, PALETTE[k % len(PALETTE)])
        curves = [t for t in fig["data"] if not is_guide(t)]
        named = [t for t in curves if t.get("showlegend", True) is not False]
        # positions by identity: `trace in named` compares dicts by value, which for
        # numpy arrays of different lengths raises (a 500 found on POST /figures/tradeoff)
        slot = {id(t): i for i, t in enumerate(named)}
        for j, trace in enumerate(curves):
            t = copy.copy(trace)
            t["legendgroup"] = label
            if t.get("showlegend", True) is not False:
                t["name"] = label if len(named) == 1 else f"{t.get('name', '')} · {label}"
                # the first figure's entries say what each line style is; every other
                # figure gets one entry, its label, that shows or hides all its curves
                # (ten entries for five roughnesses squashed the plot to a strip)
                if k > 0 and len(named) > 1:
                    if slot[id(trace)] == 0:
                        t["name"] = label
                    else:
                        t["showlegend"] = False
            line = dict(t.get("line") or {})
            if line.get("width", 1) != 0:
                line["color"] = colour
                line["dash"] = DASHES[slot[id(trace)] % len(DASHES)] if id(trace) in slot else "solid"
            t["line"] = line
            if "marker" in t:
                t["marker"] = {**t["marker"], "color": colour}
            if "error_y" in t:
                t["error_y"] = {**t["error_y"], "color": colour}
            if t.get("fill") or "fillcolor" in t:
                t["fillcolor"] = _rgba(colour, FILL_ALPHA)
            traces.append(t)
        if k == 0:
            traces.extend(t for t in fig["data"] if is_guide(t))
    layouts = [copy.deepcopy(f.get("layout", {})) for f in figures]
    for key in list(layouts[0]):
        if key.startswith(("xaxis", "yaxis")):
            _merge_ranges(layouts, (key,))
    if "polar" in layouts[0]:
        _merge_ranges(layouts, ("polar", "radialaxis"))
    layout = layouts[0]
    layout["title"] = {**(layout.get("title") or {}),
                       "text": title if title is not None else comparison_title(figures, labels)}
    layout["showlegend"] = True
    annotations = []
    for lay in layouts:
        for a in lay.get("annotations", []) or []:
            if a not in annotations:
                annotations.append(a)
    if annotations:
        layout["annotations"] = annotations
    return {"data": traces, "layout": layout}
