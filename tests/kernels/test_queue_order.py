"""The background compiler's order: loops asked for again go before those queued earlier
(the start-up list, or a model a script touched twice long ago) — what is in use now is
compiled next. The compile itself is replaced by a recorder here: what is tested is the
order in which the one background thread takes the queue."""
from __future__ import annotations

import threading
import time

import pytest

from app import kernels
from app.model import make_spec

pytestmark = pytest.mark.skipif(not kernels.ENABLED, reason="numba absent or BRDF_FAST=0")


def test_a_model_asked_again_is_compiled_before_those_queued_earlier(monkeypatch):
    started, release, order = threading.Event(), threading.Event(), []

    def build(key, note=""):
        order.append(key)
        if len(order) == 1:              # the first start-up model is being compiled
            started.set()
            release.wait(10)
        return None                      # nothing becomes ready: the queue only empties

    for name, value in (("_queue", []), ("_ready", {}), ("_failed", {}), ("_told_numpy", set()),
                        ("_build", build), ("_compile_elsewhere", lambda key: "")):
        monkeypatch.setattr(kernels, name, value)
    queued = [make_spec(ndf=n).brdf() for n in ("ggx", "beckmann", "gtr")]
    asked = make_spec(ndf="student_t").brdf()
    kernels.start([(b, "f") for b in queued])
    assert started.wait(10)
    assert kernels.lookup(asked, "f") is None       # the first ask queues nothing
    assert kernels.lookup(asked, "f") is None       # the second queues it
    release.set()
    deadline = time.monotonic() + 10
    while len(order) < 4 and time.monotonic() < deadline:
        time.sleep(0.01)
    assert [k[0] for k in order] == [kernels.components(b) for b in (queued[0], asked, *queued[1:])]
