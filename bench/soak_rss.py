"""The soak's memory sampling: each uvicorn worker's memory by process kind.

Memory here is the proportional set size (PSS, /proc/<pid>/smaps_rollup): a process's
resident pages with each page it shares split between the processes that share it.
Summed over a tree it counts every page once. RSS does not: Chromium's processes share
their libraries and the zygote's pages, and as each touches more of them the tree's RSS
sum climbed ~1 MB/min in the soak while its PSS stayed flat (a renderer alone over 280
lobe PNGs: RSS 396 → 405 MB, PSS 175 → 125 MB).

Beside PSS, each kind's *anonymous* PSS (Pss_Anon + Pss_Shmem): a process's own heap,
shared only within its tree (fork's copy-on-write pages), so what a leak grows and
nothing else moves. PSS also holds file-backed pages (the interpreter's and numpy's
libraries, chromium's ~250 MB binary), clean and bounded by the files' size, whose share
is divided among every process on the machine that maps them: another engineer's
browser test starting or ending moved one idle Chromium tree's PSS by ~110 MB while its
anonymous memory stayed within 199-210 MB (2026-12-08, 1 500 images in one process).

A uvicorn worker (a child of the master) owns a process tree: its heavy pool's
processes (app/work/pool.py), the headless Chromium of its PNG exports (app/export/
image.py, with its renderer and helper processes below it) and anything else. Summing
the tree hid which of them grew; here each descendant is counted under the kind of the
worker's direct child it descends from, told apart by that child's command line
(/proc/<pid>/cmdline).

A pool process killed at a job's budget is replaced by a fresh one that starts small
(~110 MB: the interpreter and the application's imports) and grows back while it warms:
the allocator's arenas at its first big job, tables and compiled kernels (loaded once a
model is in use) as it meets each kind of job, which in the soak (one worst case every
20 s, ten kinds, two workers) takes minutes. That climb is a renewal, not a leak. So a
kind's slope is the slope of the *life* (the same pids of that kind's direct children)
that was alive when the measured window began, with its age then; lives born in the
window are reported apart: how many, and whether the newest grew past the largest size
of those before it (a leak would; a warm-up climbs back to it at most).
"""
from __future__ import annotations

from pathlib import Path

#: the kinds, in the order they are reported
KINDS = ("own", "pool", "chromium", "other")
#: fewest samples a life needs for a slope (two points give a slope, three a fit)
MIN_LIFE_SAMPLES = 3


def _kind(cmdline: str) -> str:
    """A worker's direct child's kind, from its command line."""
    if "chrom" in cmdline or "headless_shell" in cmdline:
        return "chromium"
    if "multiprocessing.spawn" in cmdline or "spawn_main" in cmdline:
        return "pool"        # a spawned ProcessPoolExecutor process (the resource tracker is not)
    return "other"


def _processes() -> dict[int, tuple[int, int, str, int]]:
    """pid → (parent pid, PSS bytes, command line, anonymous PSS bytes) of every process
    we can read."""
    out = {}
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            ppid = int((d / "stat").read_text().rsplit(")", 1)[1].split()[1])
            pss = anon = 0
            for line in (d / "smaps_rollup").read_text().splitlines():
                if line.startswith("Pss:"):
                    pss = int(line.split()[1]) * 1024
                elif line.startswith(("Pss_Anon:", "Pss_Shmem:")):
                    anon += int(line.split()[1]) * 1024
            cmd = (d / "cmdline").read_bytes().replace(b"\0", b" ").decode(errors="replace")
        except (OSError, ValueError, IndexError):
            continue
        out[int(d.name)] = (ppid, pss, cmd, anon)
    return out


#: where a kind's anonymous PSS is in its tuple (PSS is [0], the pids [1])
ANON = 2


def sample(master: int) -> dict[int, dict[str, tuple[int, frozenset, int]]]:
    """For each uvicorn worker (the master's child): kind → (PSS bytes of that kind's
    processes and all their descendants, the pids of that kind's direct children, their
    anonymous PSS bytes)."""
    procs = _processes()
    children: dict[int, list[int]] = {}
    for pid, (ppid, _, _, _) in procs.items():
        children.setdefault(ppid, []).append(pid)

    def tree(pid: int, field: int = 1) -> int:
        return procs[pid][field] + sum(tree(c, field) for c in children.get(pid, ()))

    out = {}
    for worker in children.get(master, ()):
        if "resource_tracker" in procs[worker][2]:     # multiprocessing's, not a worker
            continue
        kinds: dict[str, list] = {k: [0, set(), 0] for k in KINDS}
        kinds["own"] = [procs[worker][1], {worker}, procs[worker][3]]
        for child in children.get(worker, ()):
            k = kinds[_kind(procs[child][2])]
            k[0] += tree(child)
            k[1].add(child)
            k[2] += tree(child, 3)
        out[worker] = {k: (b, frozenset(p), a) for k, (b, p, a) in kinds.items()}
    return out


def slope_mb_per_min(points: list[tuple[float, float]]) -> float | None:
    """Least-squares slope of (t seconds, MB) points in MB per minute."""
    if len(points) < MIN_LIFE_SAMPLES:
        return None
    tm = sum(t for t, _ in points) / len(points)
    bm = sum(b for _, b in points) / len(points)
    den = sum((t - tm) ** 2 for t, _ in points)
    return 60.0 * sum((t - tm) * (b - bm) for t, b in points) / den if den else None


def lives(samples: list[tuple[float, int, frozenset]], since: float) -> dict:
    """A kind's memory over the window from ``since`` (s) of samples (t s, bytes, the
    kind's pids) of the whole run: the slope of the life alive at ``since`` (MB/min), its
    age then and how long it lived on in the window (s: a short span's slope is noise), the slope across lives, the renewals in the window, and for the
    newest life born in it its last MB against the largest MB of the lives before it
    (over the whole run: what the process it replaced had grown to)."""
    born: dict[frozenset, float] = {}
    for t, _, pids in samples:
        born.setdefault(pids, t)
    window = [(t, b / 2**20, pids) for t, b, pids in samples if t >= since]
    if not window:
        return {"mb_per_min": None, "age_s": None, "span_s": 0, "across_mb_per_min": None, "renewals": 0,
                "end_mb": 0.0, "newest_end_mb": None, "before_max_mb": None}
    first = window[0][2]
    renewals = sum(a[2] != b[2] for a, b in zip(window, window[1:]))
    newest = window[-1][2]
    return {
        "mb_per_min": slope_mb_per_min([(t, b) for t, b, pids in window if pids == first]),
        "age_s": round(window[0][0] - born[first]),
        "span_s": round(max(t for t, _, pids in window if pids == first) - window[0][0]),
        "across_mb_per_min": slope_mb_per_min([(t, b) for t, b, _ in window]),
        "renewals": renewals,
        "end_mb": window[-1][1],
        "newest_end_mb": window[-1][1] if renewals else None,
        "before_max_mb": max((b / 2**20 for t, b, _ in samples if t < born[newest]), default=None)
        if renewals else None,
    }
