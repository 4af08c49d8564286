"""MERL .binary: layout, indexing against the published reader, and the round trip of a
known analytic model within the format's quantisation."""
import math

import numpy as np
import pytest

from app.datasets import formats, merl
from app.errors import ParameterError
from app.model import make_spec
from app.physics.vectors import direction_deg

from . import known, merl_reference as ref


def random_pairs(n, seed=0, max_theta=89.0):
    rng = np.random.default_rng(seed)
    angles = [rng.uniform(0, max_theta, n), rng.uniform(-180, 180, n),
              rng.uniform(0, max_theta, n), rng.uniform(-180, 180, n)]
    return angles, direction_deg(angles[0], angles[1]), direction_deg(angles[2], angles[3])


def test_the_closed_form_is_the_apps_model():
    _, l, v = random_pairs(500)
    app_f = make_spec(**known.model("r")).brdf().f(l, v)
    np.testing.assert_allclose(app_f, known.ggx_f(l, v), rtol=1e-10)


def test_layout_header_and_channel_scales():
    stored = np.full((3,) + merl.DIMS, 1500.0)
    stored[:, 5, 6, 7] = -1.0
    content = np.array([90, 90, 180], "<i4").tobytes() + stored.astype("<f8").tobytes()
    assert len(content) == merl.FILE_BYTES == 34_992_012
    table = merl.read(content)
    np.testing.assert_allclose(table[:, 0, 0, 0], [1.0, 1.15, 1.66], rtol=1e-15)
    assert (table[:, 5, 6, 7] < 0).all()
    assert merl.write(table) == content


def test_cells_are_the_published_readers():
    """Every channel of every cell holds its own flat index: a lookup must return the
    value the transcribed reader finds, at random direction pairs."""
    flat = np.arange(3 * merl.CELLS, dtype=float)
    table = merl.read(np.array(merl.DIMS, "<i4").tobytes() + flat.astype("<f8").tobytes())
    (ti, pi, to, po), l, v = random_pairs(3000, seed=1)
    ours = merl.lookup(table, l, v)
    for n in range(ti.size):
        theirs = ref.lookup_brdf_val(flat, *(math.radians(a[n]) for a in (ti, pi, to, po)))
        np.testing.assert_allclose(ours[:, n], theirs, rtol=1e-15)


def test_reciprocity_folds_phi_d_like_the_reader():
    table = formats.load(known.merl_bytes()).table
    _, l, v = random_pairs(2000, seed=2)
    np.testing.assert_array_equal(merl.lookup(table, l, v), merl.lookup(table, v, l))


def _cell_corners(i, j, k):
    """Direction pairs at the 8 corners of cell (i, j, k), by the reader's rotations."""
    out = []
    for th in (90.0 * (i / 90.0) ** 2, 90.0 * ((i + 1) / 90.0) ** 2):
        for td in (j, j + 1.0):
            for pd in (k, k + 1.0):
                pairs = []
                for phi in (pd, pd + 180.0):          # l, and v = d mirrored about h
                    d = [math.sin(math.radians(td)) * math.cos(math.radians(phi)),
                         math.sin(math.radians(td)) * math.sin(math.radians(phi)),
                         math.cos(math.radians(td))]
                    pairs.append(ref.rotate_vector(d, (0.0, 1.0, 0.0), math.radians(th)))
                out.append(pairs)
    return np.array(out)


def test_round_trip_reproduces_the_model_within_the_cells():
    """Read back, the file gives at any direction pair a value between the model's least
    and largest over that pair's cell (its corners and the pair itself): the format's
    quantisation and nothing more. Per channel, with each channel's scale."""
    table = formats.load(known.merl_bytes()).table
    (ti, pi, to, po), l, v = random_pairs(400, seed=3, max_theta=80.0)
    got = merl.lookup(table, l, v)
    cells = np.stack(merl.cell_of(*merl.half_diff(l, v)[:3]), axis=-1)
    within = []
    for c, name in enumerate("rgb"):
        for n, (i, j, k) in enumerate(cells):
            corners = _cell_corners(i, j, k)
            lv = corners[:, 0], corners[:, 1]
            ok = (lv[0][:, 2] > 0) & (lv[1][:, 2] > 0)
            if not ok.all() or got[c, n] < 0:
                continue   # a cell that reaches below the horizon
            values = np.append(known.ggx_f(*lv, f0=known.F0[name]),
                               known.ggx_f(l[n], v[n], f0=known.F0[name]))
            assert values.min() * (1 - 1e-12) <= got[c, n] <= values.max() * (1 + 1e-12)
            within.append(abs(got[c, n] / known.ggx_f(l[n], v[n], f0=known.F0[name]) - 1))
    assert len(within) > 1000
    assert np.median(within) < 0.02    # the typical quantisation of 1° cells


@pytest.mark.parametrize("content, says", [
    (np.array([90, 90, 180], "<i4").tobytes() + b"\0" * 800, "truncated"),
    (np.array([90, 90, 360], "<i4").tobytes() + b"\0" * 80, "90 × 90 × 360"),
    (np.array([90, 90, 180], "<i4").tobytes() + b"\0" * (merl.FILE_BYTES - 4), "longer"),
    (b"\x05\x00", "12 bytes"),
])
def test_bad_files_name_what_is_wrong(content, says):
    with pytest.raises(ParameterError) as info:
        formats.load(content, "merl")
    assert says in info.value.message and info.value.status == 422


def test_a_non_finite_value_is_refused():
    stored = np.zeros(3 * merl.CELLS)
    stored[12345] = np.inf
    with pytest.raises(ParameterError, match="finite"):
        merl.read(np.array(merl.DIMS, "<i4").tobytes() + stored.astype("<f8").tobytes())
