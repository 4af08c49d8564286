"""The soak's memory accounting (bench/soak_rss.py): a pool process renewed in the measured
window is reported as a renewal, not as a leak of the worker; a process growing through its
one life is. The soak once read a renewed pool process's climb back to its warm size
(~110 → ~290 MB over its first jobs) as +12 MB/min of one worker."""
from __future__ import annotations

import os
import signal
import subprocess
import sys
import time
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "bench"))
import soak_rss  # noqa: E402

MB = 2**20
OLD, NEW = frozenset({101}), frozenset({202})


def test_a_renewal_is_not_a_slope():
    """A process flat at 290 MB killed at t=100 and replaced by one climbing back from
    110 MB: the life alive at the window's start is flat; the renewal is counted and its
    newest process ends below what the old one held."""
    samples = [(t, 290 * MB, OLD) for t in range(0, 100, 2)]
    samples += [(t, (110 + 3 * (t - 100)) * MB, NEW) for t in range(100, 160, 2)]
    v = soak_rss.lives(samples, since=60)
    assert abs(v["mb_per_min"]) < 0.1 and v["age_s"] == 60
    assert v["renewals"] == 1
    assert v["newest_end_mb"] < v["before_max_mb"] == 290
    assert v["across_mb_per_min"] < 0          # what summing across lives read instead


def test_growth_within_one_life_is_a_slope():
    samples = [(t, (200 * MB + t * MB // 2)) for t in range(0, 120, 2)]
    v = soak_rss.lives([(t, b, OLD) for t, b in samples], since=60)
    assert v["renewals"] == 0 and abs(v["mb_per_min"] - 30.0) < 0.5


def _worker_like(child: str, argv_tag: str) -> subprocess.Popen:
    """A worker-like process (a child of this test) whose one child runs ``child`` with
    ``argv_tag`` in its command line (which names its kind)."""
    worker = (f"import subprocess, sys, time; p = subprocess.Popen([sys.executable, '-c', "
              f"{child!r}, {argv_tag!r}]); time.sleep(30)")
    return subprocess.Popen([sys.executable, "-c", worker])


def _sample_until(proc, kind: str, above: int) -> dict:
    deadline = time.monotonic() + 20
    while time.monotonic() < deadline:
        kinds = soak_rss.sample(os.getpid()).get(proc.pid)
        if kinds and kinds[kind][0] > above:
            return kinds
        time.sleep(0.1)
    raise AssertionError(f"{kind} never above {above / MB:.0f} MB: {kinds}")


def _kill_tree(proc) -> None:
    """This test's processes, by pid, deepest first."""
    procs, mine = soak_rss._processes(), [proc.pid]
    for pid in mine:
        mine += [c for c, (ppid, *_) in procs.items() if ppid == pid]
    for pid in reversed(mine):
        try:
            os.kill(pid, signal.SIGKILL)
        except ProcessLookupError:
            pass
    proc.wait()


def test_sample_counts_a_workers_descendants_by_kind():
    """A spawn_main child whose own child holds memory: the grandchild counts under the
    pool kind of its parent."""
    grandchild = "import time; b = bytearray(64 * 2**20); time.sleep(30)"
    child = (f"import subprocess, sys, time; p = subprocess.Popen([sys.executable, '-c', {grandchild!r}]); "
             "time.sleep(30)")
    proc = _worker_like(child, "spawn_main")
    try:
        kinds = _sample_until(proc, "pool", 64 * MB)
        assert kinds["own"][1] == {proc.pid} and len(kinds["pool"][1]) == 1
        assert kinds["chromium"][0] == 0
    finally:
        _kill_tree(proc)


def test_pages_a_tree_shares_count_once():
    """A child holding 64 MB forks a copy that shares every page (as Chromium's processes
    share their libraries and the zygote's pages): the tree's sum counts them once, where
    the two processes' RSS sum counted them twice."""
    child = ("import os, time; b = bytearray(64 * 2**20)\n"
             "if os.fork() == 0: time.sleep(30)\n"
             "time.sleep(30)")
    proc = _worker_like(child, "other-kind")
    try:
        kinds = _sample_until(proc, "other", 64 * MB)
        time.sleep(0.5)                   # the fork has happened by now
        kinds = soak_rss.sample(os.getpid())[proc.pid]
        procs = soak_rss._processes()
        tree = [c for c, (ppid, *_) in procs.items() if ppid in kinds["other"][1]]
        assert len(tree) == 1, "the fork's copy"
        assert 64 * MB < kinds["other"][0] < 64 * MB + 40 * MB, kinds["other"][0] / MB
    finally:
        _kill_tree(proc)
