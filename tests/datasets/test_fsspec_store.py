"""The data-set store at an fsspec URL, on an S3-compatible server started here (moto):
what several hosts need (issue 36). Two stores over one URL stand for two hosts, a new one
for a host after a restart; the two applications of the last test, for two hosts behind a
load balancer. Its policy, the same as the directory store's, is in test_shared_store.py."""
from __future__ import annotations

import time
import warnings

import numpy as np
import pytest
from fsspec.registry import known_implementations

from app.config import Settings
from app.datasets import formats
from app.datasets.disk_store import DiskDatasetStore
from app.datasets.fsspec_store import FsspecDatasetStore
from app.errors import ParameterError
from app.main import create_app
from tests.budget import settings_for_tests
from tests.datasets.s3 import s3_bucket, s3_client, s3_endpoint, s3_url  # noqa: F401  (fixtures)
from tests.datasets.uploads import CSV, put, random_csv

with warnings.catch_warnings():
    warnings.simplefilter("ignore", DeprecationWarning)
    from fastapi.testclient import TestClient


def test_an_upload_on_one_host_is_served_by_another_and_after_a_restart(s3_url):
    one, other = FsspecDatasetStore(s3_url, 10**8), FsspecDatasetStore(s3_url, 10**8)
    data_id, token, _ = put(one, CSV)
    data, info = other.get(data_id)
    expected = formats.load(CSV)
    assert np.array_equal(data.f, expected.f) and np.array_equal(data.l, expected.l)
    assert np.array_equal(data.v, expected.v) and info["count"] == 2
    restarted = FsspecDatasetStore(s3_url, 10**8)
    assert data_id in restarted and restarted.get(data_id)[1] == info
    restarted.delete(data_id, token)                      # the token works on any host
    with pytest.raises(ParameterError) as err:
        one.get(data_id)
    assert err.value.status == 410 and "(deleted)" in err.value.message


def test_an_eviction_on_one_host_answers_410_on_another(s3_url):
    one = FsspecDatasetStore(s3_url, 10**8)
    first, _, _ = put(one, random_csv(200, 1), client="a")
    small = FsspecDatasetStore(s3_url, int(one.bytes * 1.5))
    put(small, random_csv(200, 2), client="b")
    with pytest.raises(ParameterError) as err:
        one.get(first)
    assert err.value.status == 410 and "least recently used" in err.value.message


def test_the_objects_are_the_directory_stores_files_plus_one_use_marker(s3_url, s3_bucket,
                                                                      s3_client, tmp_path):
    """One PUT an object, no temporary objects (a PUT is atomic); a read leaves
    ``<id>.npz.used``, since it cannot touch an object's time."""
    bucket, directory = FsspecDatasetStore(s3_url, 10**8), DiskDatasetStore(tmp_path, 10**8)
    for store in (bucket, directory):
        kept, _, _ = put(store, random_csv(30, 1))
        gone, token, _ = put(store, random_csv(30, 2))
        store.delete(gone, token)
        store.get(kept)
    keys = {o["Key"] for o in s3_client.list_objects_v2(Bucket=s3_bucket)["Contents"]}
    files = {p.name for p in tmp_path.iterdir()} - {".lock"}
    assert keys == {f"datasets/{name}" for name in files | {f"{kept}.npz.used"}}
    assert files == {f"{kept}.npz", f"{kept}.json", f"{gone}.gone"}


def test_a_read_on_one_host_keeps_a_data_set_on_another(s3_url):
    """The use marker is the server's clock, which every host shares."""
    probe = FsspecDatasetStore(f"{s3_url}-probe", 10**8)
    put(probe, random_csv(100, 0))
    one, other = (FsspecDatasetStore(s3_url, int(probe.bytes * 2.5)) for _ in range(2))
    a, _, _ = put(one, random_csv(100, 1))
    b, _, _ = put(one, random_csv(100, 2))
    time.sleep(1.05)                                       # S3's times count whole seconds
    other.get(a)
    put(one, random_csv(100, 3))
    assert a in one and b not in one


def test_a_missing_backend_stops_the_server_at_start_up_naming_the_extra(monkeypatch):
    """A URL whose fsspec backend is not installed: an error naming BRDF_DATA_URL, the
    package and the extra, when the settings are read (the server's start), not a 500."""
    monkeypatch.setitem(known_implementations, "brdftest",
                        {"class": "brdf_no_such_package.FileSystem",
                         "err": "Install brdf_no_such_package to use brdftest://"})
    monkeypatch.setenv("BRDF_DATA_URL", "brdftest://bucket/datasets")
    with pytest.raises(ValueError) as err:
        Settings.from_env()
    message = str(err.value)
    assert message.startswith("BRDF_DATA_URL='brdftest://bucket/datasets'")
    assert "brdf_no_such_package" in message and "[s3]" in message
    with pytest.raises(ImportError, match=r"brdf_no_such_package.*\[s3\]"):
        FsspecDatasetStore("brdftest://bucket/datasets", 10**8)
    monkeypatch.setenv("BRDF_DATA_URL", "s3://bucket/datasets")     # installed: read as given
    assert Settings.from_env().data_url == "s3://bucket/datasets"


def test_two_applications_on_one_bucket_serve_each_others_uploads(s3_url):
    settings = settings_for_tests(data_url=s3_url)
    one, other = TestClient(create_app(settings)), TestClient(create_app(settings))
    uploaded = one.post("/api/v1/datasets", content=CSV, headers={"content-type": "text/csv"})
    assert uploaded.status_code == 201
    body = uploaded.json()
    served = other.get(f"/api/v1/datasets/{body['id']}")
    assert served.status_code == 200 and served.json()["summary"] == body["summary"]
    assert served.json()["summary"]["count"] == 2
    assert other.delete(f"/api/v1/datasets/{body['id']}", params={"token": "wrong"}).status_code == 403
    assert other.delete(f"/api/v1/datasets/{body['id']}", params={"token": body["token"]}).status_code == 204
    gone = one.get(f"/api/v1/datasets/{body['id']}")
    assert gone.status_code == 410 and "deleted" in gone.text
