"""The data-set store's policy, the same over every backend (issue 36): the directory
store (every worker of one host) and the fsspec store on an S3-compatible server started
here (every worker of every host). Bounded with 410 and the reason, the least recently
used first; a per-client quota; delete by token only; a damaged file answers 410 and is
stored anew by the next upload."""
from __future__ import annotations

import time

import numpy as np
import pytest

from app.datasets import formats
from app.datasets.backends import open_store
from app.datasets.disk_store import DiskDatasetStore
from app.datasets.fsspec_store import FsspecDatasetStore
from app.errors import ParameterError
from tests.datasets.s3 import s3_bucket, s3_client, s3_endpoint, s3_url  # noqa: F401  (fixtures)
from tests.datasets.uploads import CSV, put, random_csv

#: seconds between two uses that every backend tells apart: S3's LastModified counts
#: whole seconds; a file's mtime follows the kernel's clock tick (a few ms)
TELLS_APART = {"directory": 0.05, "s3": 1.05}


def _status(store, data_id: str) -> tuple[int, str]:
    try:
        store.get(data_id)
    except ParameterError as err:
        return err.status, err.message
    return 200, ""


class Backend:
    """Stores of one backend: ``open(name, max_bytes, client_bytes)`` at location
    ``name`` (the same name: the same data, as another worker sees it)."""

    def __init__(self, kind: str, base: str):
        self.kind, self.base = kind, base

    def open(self, name: str, max_bytes: int, client_bytes: int | None = None):
        return open_store(f"{self.base}/{name}", max_bytes, client_bytes)

    def tick(self) -> None:
        time.sleep(TELLS_APART[self.kind])


@pytest.fixture(params=["directory", "s3"])
def backend(request, tmp_path):
    if request.param == "directory":
        return Backend("directory", str(tmp_path))
    return Backend("s3", request.getfixturevalue("s3_url"))


def test_a_location_names_its_backend(backend):
    store = backend.open("x", 10**8)
    assert isinstance(store, DiskDatasetStore if backend.kind == "directory" else FsspecDatasetStore)


def test_an_evicted_id_answers_410_with_the_reason_and_an_unknown_one_404(backend):
    first = backend.open("s", 10**8)
    a, _, _ = put(first, random_csv(200, 1), client="a")
    size = first.bytes
    small = backend.open("s", int(size * 1.5))
    b, _, _ = put(small, random_csv(200, 2), client="b")
    status, message = _status(small, a)
    assert status == 410 and "least recently used" in message and "BRDF_MAX_DATASETS_BYTES" in message
    assert small.get(b)[0].count == 200 and small.bytes == size
    assert _status(small, "0" * 32)[0] == 404


def test_a_read_keeps_a_data_set_and_the_least_recently_used_goes(backend):
    probe = backend.open("probe", 10**8)
    put(probe, random_csv(200, 0))
    size = probe.bytes
    store = backend.open("s", int(size * 2.5))             # room for two
    a, _, _ = put(store, random_csv(200, 1))
    b, _, _ = put(store, random_csv(200, 2))
    backend.tick()
    store.get(a)                                            # a used after b
    c, _, _ = put(store, random_csv(200, 3))
    assert [_status(store, i)[0] for i in (a, b, c)] == [200, 410, 200]


def test_one_client_cannot_evict_anothers_data_set(backend):
    probe = backend.open("probe", 10**8)
    put(probe, random_csv(200, 0))
    size = probe.bytes
    store = backend.open("s", max_bytes=int(size * 4.5), client_bytes=int(size * 2.5))
    theirs, _, _ = put(store, random_csv(200, 10), client="alice")
    mallorys = [put(store, random_csv(200, seed), client="mallory")[0] for seed in range(11, 16)]
    assert store.get(theirs)[0].count == 200
    assert store.bytes == 3 * size                          # alice's one and two of mallory's
    answers = [_status(store, i) for i in mallorys]
    assert sorted(status for status, _ in answers) == [200, 200, 410, 410, 410]
    assert all(f"quota of {int(size * 2.5)} bytes" in message for status, message in answers
               if status == 410)
    assert _status(store, mallorys[-1])[0] == 200           # the newest stays


def test_delete_needs_the_uploads_token(backend):
    store = backend.open("s", 10**8)
    data_id, token, _ = put(store, CSV)
    for wrong in (None, "", "not-the-token"):
        with pytest.raises(ParameterError) as err:
            store.delete(data_id, wrong)
        assert err.value.status == 403
    store.delete(data_id, token)
    assert _status(store, data_id) == (410, f"data set {data_id} has expired (deleted); upload it again")


def test_a_damaged_file_answers_410_and_the_next_upload_stores_it_anew(backend):
    store = backend.open("s", 10**8)
    data_id, _, _ = put(store, CSV)
    whole = store.files.read(data_id + ".npz")
    store.files.write(data_id + ".npz", whole[:len(whole) // 2])     # other hands cut it
    status, message = _status(store, data_id)
    assert status == 410 and "damaged" in message
    put(store, CSV)
    data, info = store.get(data_id)
    assert np.array_equal(data.f, formats.load(CSV).f) and info["count"] == 2


def test_only_some_evictions_are_remembered(backend, monkeypatch):
    from app.datasets import shared_store
    monkeypatch.setattr(shared_store, "REMEMBERED_EVICTIONS", 2)
    store = backend.open("s", 10**8)
    ids = []
    for seed in range(4):
        data_id, token, _ = put(store, random_csv(20, seed))
        store.delete(data_id, token)
        ids.append(data_id)
    put(store, CSV)               # an upload forgets two, the oldest (S3: any, in one second)
    assert sorted(_status(store, i)[0] for i in ids) == [404, 404, 410, 410]
