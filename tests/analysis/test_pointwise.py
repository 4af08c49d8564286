"""The pointwise metric's relative error at the points where f diverges (both directions
at 90°): it was NaN there (∞/∞), and an argmax that met the NaN skipped the whole α, so
an alternative could look better than it is."""
import warnings

import numpy as np

from app.analysis.pointwise import F_FLOOR, relative_error


def test_relative_error_is_defined_where_the_reference_diverges():
    ref = np.array([np.inf, np.inf, 1.0, 1.0, 0.0])
    alt = np.array([np.inf, 2.0, np.inf, 1.5, F_FLOOR])
    with warnings.catch_warnings():
        warnings.simplefilter("error")
        err = relative_error(ref, alt)
    assert not np.isnan(err).any()
    assert err[0] == 0.0 and err[1] == 0.0       # not counted where f has no finite value
    assert err[2] == np.inf                       # diverging where the reference is finite
    assert err[3] == 0.5 and err[4] == 1.0        # |Δf| / max(f, floor)
    assert int(np.argmax(err[1:])) == 1           # the worst point is found, not a NaN
