"""The tradeoff plot never draws an error below its own reference's bound: a difference
of 3e-16 against a reference good to 2.5e-10 is not resolved, and is drawn at the bound,
marked "≤ bound"."""
import numpy as np

from app.figures.tradeoff import tradeoff_figure

REF = 2.5e-10
SPEC = {"ndf": "ggx", "alpha": 0.3, "fresnel": "none", "masking": "smith", "g2": "height_correlated", "kd": 0.0}


def _data():
    # quadrature converging to the rounding floor, Monte Carlo well above the bound
    return {"methods": ["quadrature", "mc_vndf"], "method_index": [0, 0, 0, 1, 1],
            "evaluations": [10.0, 100.0, 1000.0, 100.0, 1000.0],
            "seconds": [1e-4, 1e-3, 1e-2, 1e-3, 1e-2], "budget": [1, 2, 3, 1, 2],
            "error": [1e-3, 4e-12, 3e-16, 0.05, 0.01], "E_error": [2e-3, 1e-11, 1e-15, 0.05, 0.015],
            "within_reported": [1.0] * 5, "reference_error": REF, "mu_count": 8, "timing": ""}


def _measured(fig, method):
    return next(t for t in fig["data"] if t.get("name") == method)


def test_no_error_is_drawn_below_the_reference_bound():
    fig = tradeoff_figure(_data(), SPEC)
    quad = _measured(fig, "quadrature")
    drawn = [y for y in quad["y"] if y is not None]
    assert min(drawn) >= REF
    # the resolved point keeps its value; the two unresolved ones are marked
    assert drawn[0] == 1e-3
    assert [s != "circle" for s in quad["marker"]["symbol"]] == [False, True, True]
    assert all("bound" in t for t in quad["text"][1:])
    assert any("≤ bound" in (t.get("name") or "") for t in fig["data"])
    mc = _measured(fig, "mc_vndf")
    assert mc["y"] == [0.05, 0.01] and set(mc["marker"]["symbol"]) == {"circle"}
