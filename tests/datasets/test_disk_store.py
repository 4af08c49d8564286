"""The data-set store on disk: shared by separate processes, kept across a restart,
bounded with 410 and the reason, a per-client quota, delete by token only, and no
temporary file left by a dead writer (issue 36)."""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numpy as np
import pytest

from app.datasets import formats, summary
from app.datasets.disk_store import DiskDatasetStore
from app.datasets.store import content_id
from app.errors import ParameterError

CSV = b"theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n30,0,30,180,1.5\n45,0,20,90,0.25\n"


def _csv(n: int, seed: int) -> bytes:
    rng = np.random.default_rng(seed)
    rows = np.column_stack([rng.uniform(0, 89, n), rng.uniform(0, 360, n), rng.uniform(0, 89, n),
                            rng.uniform(0, 360, n), rng.uniform(0, 2, n)])
    return ("theta_i_deg,phi_i_deg,theta_o_deg,phi_o_deg,f\n"
            + "\n".join(",".join(f"{x:.6f}" for x in r) for r in rows)).encode()


def _put(store, content: bytes, client: str = ""):
    data = formats.load(content)
    data_id = content_id(data.format, content)
    return data_id, store.put(data_id, data, summary.summarize(data), client=client), data


def test_another_process_sees_an_upload_and_a_new_store_still_serves_it(tmp_path):
    code = textwrap.dedent(f"""
        from app.datasets import formats, summary
        from app.datasets.disk_store import DiskDatasetStore
        from app.datasets.store import content_id
        content = {CSV!r}
        data = formats.load(content)
        data_id = content_id(data.format, content)
        DiskDatasetStore({str(tmp_path)!r}, 10**8).put(data_id, data, summary.summarize(data))
        print(data_id)
    """)
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True,
                         cwd=os.path.dirname(os.path.dirname(os.path.dirname(__file__))))
    data_id = out.stdout.strip()
    data, info = DiskDatasetStore(tmp_path, 10**8).get(data_id)     # another process, a "restart"
    expected = formats.load(CSV)
    assert np.array_equal(data.f, expected.f) and np.array_equal(data.l, expected.l)
    assert data.channels == expected.channels and info["count"] == 2


def test_an_evicted_id_answers_410_with_the_reason_and_an_unknown_one_404(tmp_path):
    first = DiskDatasetStore(tmp_path, 10**8)
    a, _, _ = _put(first, _csv(200, 1), client="a")
    size = first.bytes
    small = DiskDatasetStore(tmp_path, int(size * 1.5))
    b, _, _ = _put(small, _csv(200, 2), client="b")
    with pytest.raises(ParameterError) as err:
        small.get(a)
    assert err.value.status == 410 and "least recently used" in err.value.message
    assert small.get(b)[0].count == 200
    with pytest.raises(ParameterError) as err:
        small.get("0" * 32)
    assert err.value.status == 404


def test_one_client_cannot_evict_anothers_data_set(tmp_path):
    probe = DiskDatasetStore(tmp_path / "probe", 10**8)
    _put(probe, _csv(200, 0))
    size = probe.bytes
    store = DiskDatasetStore(tmp_path / "s", max_bytes=int(size * 4.5), client_bytes=int(size * 2.5))
    theirs, _, _ = _put(store, _csv(200, 10), client="alice")
    for seed in range(11, 21):                                  # ten uploads by another client
        _put(store, _csv(200, seed), client="mallory")
    assert store.get(theirs)[0].count == 200
    assert store.bytes <= int(size * 4.5)


def test_delete_needs_the_uploads_token(tmp_path):
    store = DiskDatasetStore(tmp_path, 10**8)
    data_id, token, _ = _put(store, CSV)
    for wrong in (None, "", "not-the-token"):
        with pytest.raises(ParameterError) as err:
            store.delete(data_id, wrong)
        assert err.value.status == 403
    store.delete(data_id, token)
    with pytest.raises(ParameterError) as err:
        store.get(data_id)
    assert err.value.status == 410 and "deleted" in err.value.message


def test_temporary_files_of_a_dead_writer_are_removed(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True).stdout.strip()
    left = tmp_path / f"{'a' * 32}.npz.{dead}.tmp"
    left.write_bytes(b"x" * 1000)
    store = DiskDatasetStore(tmp_path, 10**8)
    assert not left.exists()
    data_id, _, _ = _put(store, CSV)
    assert not list(tmp_path.glob("*.tmp")) and data_id in store
