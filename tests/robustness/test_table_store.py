"""E(μ, α) tables built outside requests: at start-up in the background, persisted to a
cache directory that a restart and a second worker reuse; a request whose table is not
ready is told to retry (Busy), and method=auto takes the quadrature instead."""
from __future__ import annotations

import logging
import os
import subprocess
import sys
import textwrap
from pathlib import Path

import numpy as np
import pytest
from fastapi.testclient import TestClient

from app.config import Settings
from app.errors import Busy
from app.integrate import budget, methods, tables
from app.integrate.tables import store as table_store
from app.main import create_app
from app.model import make_spec
from tests.small_store import small_fresh_store

ROOT = Path(__file__).resolve().parents[2]
#: 16×16 grids: what is tested is where tables come from, not their accuracy
SMALL = {"TABLE_N_Y": 16, "TABLE_N_R": 16, "SLOW_TABLE_N": 16}


@pytest.fixture(autouse=True)
def small_store(monkeypatch):
    with small_fresh_store(monkeypatch, 16):
        yield


def _ggx_key(basis=None, **values):
    lobe = make_spec(**values).brdf().lobes()[0][1]
    return tables.table_key(lobe, basis)


def test_built_once_persisted_and_reused_after_a_restart(tmp_path):
    key = _ggx_key()
    assert table_store.start(tmp_path, keys=[key]) == tmp_path
    assert table_store.wait(300)
    files = list(tmp_path.glob("table-*.npz"))
    assert len(files) == 1
    built = table_store.table(key)
    # a restart: nothing in memory, the file is there: nothing is queued, nothing built
    table_store.cache_clear()
    table_store.start(tmp_path, keys=[key])
    assert table_store.building() == []
    loaded = table_store.table(key)
    assert table_store.cache_info().misses == 0
    assert loaded is not built
    mu, alpha = np.linspace(0, 1, 37), np.geomspace(1e-4, 1, 37)
    np.testing.assert_array_equal(loaded.E(mu, alpha), built.E(mu, alpha))
    assert loaded.error == built.error


def test_a_second_worker_reads_the_first_ones_file(tmp_path):
    table_store.start(tmp_path, keys=[_ggx_key()])
    assert table_store.wait(300)
    child = textwrap.dedent(f"""
        import sys
        from app.integrate.tables import store as table_store, table as tables
        from app.model import make_spec
        for name, value in {SMALL!r}.items():     # the grid the parent's small store uses
            setattr(tables, name, value)
        key = tables.table_key(make_spec().brdf().lobes()[0][1], None)
        table_store.start(sys.argv[1], keys=[key])
        queued = table_store.building()
        table_store.table(key)
        print(queued, table_store.cache_info().misses)
    """)
    out = subprocess.run([sys.executable, "-c", child, str(tmp_path)], cwd=ROOT,
                         capture_output=True, text=True, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert out.returncode == 0, out.stderr[-2000:]
    assert out.stdout.split()[-2:] == ["[]", "0"], out.stdout


def test_changed_code_does_not_read_an_old_file(tmp_path, monkeypatch):
    key = _ggx_key()
    table_store.start(tmp_path, keys=[key])
    assert table_store.wait(300)
    old = table_store._path(key)
    monkeypatch.setattr(table_store, "_version", ["another version"])
    assert table_store._path(key) != old


def test_unwritable_directory_leaves_the_tables_in_memory(tmp_path, caplog):
    blocked = tmp_path / "file"
    blocked.write_text("not a directory")
    with caplog.at_level(logging.WARNING, logger="app"):
        assert table_store.start(blocked / "tables", keys=[]) is None
    assert "not writable" in caplog.text
    assert table_store.table(_ggx_key()).values.shape == (16, 16)


def test_a_request_is_told_to_retry_while_its_table_builds(monkeypatch):
    """Predicted too slow for the request: queued for the builder, Busy names the table
    and a Retry-After; once built, the same call answers from memory."""
    monkeypatch.setattr(table_store, "predict_seconds", lambda key: 1e4)
    key = _ggx_key(ndf="beckmann")
    with budget.limit(10.0), pytest.raises(Busy) as busy:
        table_store.table(key)
    assert "ndf=beckmann" in busy.value.what and busy.value.retry_after >= 1
    assert table_store.wait(300)
    with budget.limit(10.0):
        assert table_store.table(key).values.shape == (16, 16)


def test_auto_takes_the_quadrature_until_the_table_is_built(monkeypatch):
    """auto neither builds, queues, probes nor waits for a table (nor for compiled loops):
    the quadrature answers at once; once the table exists auto takes it."""
    def no_probe(key):
        raise AssertionError("auto probed a build")
    monkeypatch.setattr(table_store, "predict_seconds", no_probe)
    brdf = make_spec(ndf="beckmann", fresnel="none").brdf()
    misses = table_store.cache_info().misses
    with budget.limit(10.0):
        method, reason = methods.choose(brdf, 1e-2)     # a 16² table's bound meets 1e-2
    assert method == "quadrature" and "not built yet" in reason
    assert table_store.cache_info().misses == misses            # nothing built here
    assert table_store.building() == []                          # nor queued
    table_store.table(tables.table_key(brdf))                   # outside a request: built
    with budget.limit(10.0):
        assert methods.choose(brdf, 1e-2)[0] == "table"


def test_outside_a_request_a_table_is_built_in_place(monkeypatch):
    monkeypatch.setattr(table_store, "predict_seconds", lambda key: 1e4)
    assert table_store.table(_ggx_key()).values.shape == (16, 16)


def test_fresh_server_answers_kulla_conty_from_its_start_up_table_and_a_restart_reuses_it(tmp_path):
    url = "/api/v1/albedo?multiscatter=kulla_conty&n=5&method=quadrature"
    settings = Settings(max_seconds=300, cache_dir=str(tmp_path))
    with TestClient(create_app(settings)) as client:
        assert table_store.wait(300)
        built = table_store.cache_info().misses
        assert built >= 2                         # GGX and Beckmann, F = 1 at least
        r = client.get(url)
        assert r.status_code == 200, r.text
        assert table_store.cache_info().misses == built     # none built by the request
    table_store.cache_clear()
    with TestClient(create_app(settings)) as client:
        assert table_store.building() == []                  # all read from disk
        r = client.get(url)
        assert r.status_code == 200, r.text
        info = table_store.cache_info()
        assert info.misses == 0 and info.hits > 0


def test_without_a_started_store_a_slow_table_is_busy_and_nothing_builds(monkeypatch):
    """An app served without its lifespan (no builder): Busy, and no thread left building."""
    table_store.stop()
    monkeypatch.setattr(table_store, "predict_seconds", lambda key: 1e4)
    with budget.limit(10.0), pytest.raises(Busy) as busy:
        table_store.table(_ggx_key(ndf="beckmann"))
    assert "no background builder" in busy.value.message and table_store.building() == []


def test_compiled_kernels_are_written_in_the_users_cache_not_the_package(monkeypatch, tmp_path):
    """Kernels are written as models compile: in the user's cache (whatever BRDF_CACHE_DIR
    says, as they are code), never inside the package, whose files the tables' code
    digest reads (a worker that compiled one more model must find the tables another saved)."""
    from app.kernels import compose
    monkeypatch.delenv("BRDF_KERNEL_DIR", raising=False)
    monkeypatch.setenv("XDG_CACHE_HOME", str(tmp_path / "xdg"))
    monkeypatch.setenv("BRDF_CACHE_DIR", str(tmp_path / "tables"))
    assert compose.kernel_dir() == tmp_path / "xdg" / "brdf-explorer" / "kernels"


def test_a_table_the_store_lets_go_is_freed_after_its_E_avg():
    """E_avg's memo holds no table alive (an lru_cache keyed by tables kept up to 1024 of
    them past the store's byte bound)."""
    import gc
    import weakref
    t = table_store.table(_ggx_key())
    assert 0.0 < t.E_avg(0.3) < 1.0
    ref = weakref.ref(t)
    del t
    table_store.cache_clear()
    gc.collect()
    assert ref() is None
