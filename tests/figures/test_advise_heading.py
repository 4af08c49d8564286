"""The advice heading says something true when the error is zero or below rounding:
"(albedo error 0 measured, ≤ 0 bound)" read as a claim of a measured perfect match."""
from app.figures.advise import advise_figure
from app.model import make_spec

RANGE = {"alpha_min": 0.05, "alpha_max": 1.0, "theta_max_deg": 90.0}


def _title(max_error, max_difference, changes=None):
    data = {"alternatives": [], "changes": changes or {}, "max_error": max_error,
            "max_difference": max_difference, "relative_cost": 1.0, "tol": 0.01, "range": RANGE}
    return advise_figure(data, make_spec().values)["layout"]["title"]["text"].split("<br>")[0]


def test_keeping_the_model_does_not_claim_a_zero_bound():
    head = _title(0.0, 0.0)
    assert "0 measured" not in head and "≤ 0 bound" not in head
    assert "rounding" in head


def test_a_difference_below_rounding_is_not_printed_as_its_digits():
    head = _title(2e-3, 3e-17, {"g2": "separable"})
    assert "3e-17" not in head and "< 1e-12 measured" in head and "≤ 0.002 bound" in head


def test_a_resolved_error_is_stated_as_before():
    head = _title(2e-3, 1.5e-3, {"g2": "separable"})
    assert "0.0015 measured, ≤ 0.002 bound" in head
