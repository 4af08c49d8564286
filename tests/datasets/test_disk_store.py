"""The data-set store in a directory: shared by separate processes, kept across a
restart, and no temporary file left by a dead writer (issue 36). Its policy, the same as
the fsspec store's, is tested over both in test_shared_store.py."""
from __future__ import annotations

import os
import subprocess
import sys
import textwrap

import numpy as np

from app.datasets import formats
from app.datasets.disk_store import DiskDatasetStore
from tests.datasets.uploads import CSV, put

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


def test_temporary_files_of_a_dead_writer_are_removed(tmp_path):
    dead = subprocess.run([sys.executable, "-c", "import os; print(os.getpid())"],
                          capture_output=True, text=True, check=True).stdout.strip()
    left = tmp_path / f"{'a' * 32}.npz.{dead}.tmp"
    left.write_bytes(b"x" * 1000)
    store = DiskDatasetStore(tmp_path, 10**8)
    assert not left.exists()
    data_id, _, _ = put(store, CSV)
    assert not list(tmp_path.glob("*.tmp")) and data_id in store
