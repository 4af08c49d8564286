"""A fresh, small E(μ, α) table store for one test: tables of n × n nodes (builds in a
fraction of a second), no start-up tables, an empty cache before and after, and every
background build finished before it starts and before the next test starts."""
from __future__ import annotations

import contextlib

from app.integrate.tables import store as table_store, table as tables


@contextlib.contextmanager
def small_fresh_store(monkeypatch, n: int):
    for name in ("TABLE_N_Y", "TABLE_N_R", "SLOW_TABLE_N"):
        monkeypatch.setattr(tables, name, n)
    assert table_store.wait(300)        # builds an earlier test queued: not into this store
    table_store.start(None, keys=[])
    table_store.cache_clear()
    yield
    assert table_store.wait(300)
    table_store.stop()
    table_store.cache_clear()
