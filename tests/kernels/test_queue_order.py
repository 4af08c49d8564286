"""The background compiler's order: a model in use — its numpy work has paid the rent — goes
before those queued earlier (the start-up list, or a model in use long ago): what is in use
now is compiled next; a model used in passing is not queued at all. The compile itself is
replaced by a recorder here: what is tested is what the one background thread takes, and
in which order."""
from __future__ import annotations

import threading
import time

import numpy as np
import pytest

from app import kernels
from app.model import make_spec

pytestmark = pytest.mark.skipif(not kernels.ENABLED, reason="numba absent or BRDF_FAST=0")


def test_a_model_in_use_is_compiled_before_those_queued_earlier(monkeypatch):
    started, release, order = threading.Event(), threading.Event(), []

    def build(key, note=""):
        order.append(key)
        if len(order) == 1:              # the first start-up model is being compiled
            started.set()
            release.wait(10)
        return None                      # nothing becomes ready: the queue only empties

    for name, value in (("_queue", []), ("_ready", {}), ("_failed", {}), ("_told_numpy", set()), ("_rent", {}),
                        ("_build", build), ("_compile_elsewhere", lambda key: "")):
        monkeypatch.setattr(kernels, name, value)
    queued = [make_spec(ndf=n).brdf() for n in ("ggx", "beckmann", "gtr")]
    asked = make_spec(ndf="student_t").brdf()
    kernels.start([(b, "f") for b in queued])
    assert started.wait(10)
    key = (kernels.components(asked), "f")
    spent = time.thread_time()
    assert kernels.lookup(asked, "f") is None
    kernels.f(asked, *_directions(2000))            # a figure's worth: nothing queued
    assert key not in kernels._queue
    work = _directions(200000)
    while key not in kernels._queue and time.thread_time() - spent < 30:
        kernels.f(asked, *work)                     # in use: its numpy work pays the rent
    assert key in kernels._queue
    assert time.thread_time() - spent >= kernels.RENT_SECONDS
    release.set()
    deadline = time.monotonic() + 10
    while len(order) < 4 and time.monotonic() < deadline:
        time.sleep(0.01)
    assert [k[0] for k in order] == [kernels.components(b) for b in (queued[0], asked, *queued[1:])]


def _directions(n: int) -> tuple[np.ndarray, np.ndarray]:
    """n pairs of directions in the upper hemisphere."""
    rng = np.random.default_rng(n)
    z = rng.uniform(0.05, 1.0, (2, n))
    phi = rng.uniform(0.0, 2 * np.pi, (2, n))
    s = np.sqrt(1.0 - z * z)
    l, v = np.stack([s * np.cos(phi), s * np.sin(phi), z], axis=-1)
    return l, v
