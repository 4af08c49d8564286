"""The no-NaN check the API tests share (tests/finite.py) refuses each non-finite JSON
token, and only tokens: "NaN" spelled inside a string (a base64 array) is data."""
import pytest

from tests.finite import finite_json


@pytest.mark.parametrize("token", ["NaN", "Infinity", "-Infinity"])
def test_a_non_finite_token_fails(token):
    with pytest.raises(AssertionError, match=token.lstrip("-")):
        finite_json(f'{{"y": [1.0, {token}]}}')


def test_nan_inside_a_string_is_data():
    assert finite_json(b'{"bdata": "pkpNaNu0", "y": [1.0, null]}') == {"bdata": "pkpNaNu0", "y": [1.0, None]}
