"""Soak: minutes of mixed slider traffic on 2 workers, with worst cases and export bursts.

    python bench/soak.py                    # 10 minutes (1 warm-up, 1 baseline, 8 mixed)
    python bench/soak.py --minutes 2        # a short run, same phases scaled

One uvicorn with 2 workers on 127.0.0.1 (a fresh table cache directory, so the start-up
builds are part of the run). Phases:

1. warm-up: slider traffic, every worst case three times and one export burst (imports,
   compiles, tables, the allocator's arenas: every kind of work has run once), then the
   heavy pool's cases in rounds, so that each pool process meets each one after its
   compile (POOL_ROUNDS); not counted;
   it lasts at least a tenth of the run and until those requests are answered;
2. baseline: slider traffic only: the cheap-request latencies to compare with;
3. mixed: the same slider traffic, plus every WORST_EVERY seconds one worst case of an
   endpoint at the default limits, plus every BURST_EVERY seconds BURST PNG exports at
   once (clients that honour Retry-After: a refused export waits and retries).

Reported: status counts (every 5xx, and the 503s that said "busy" with Retry-After
apart), cheap-request p50/p99 in the baseline and in the mixed phase and their ratio, the
worst cases' times, and the workers' resident memory (from /proc) sampled every few
seconds: after warm-up, at the end, the largest, and the slope over the mixed phase's
second half (a leak keeps a slope; a cache filling to its bound flattens), in all and per
worker (each uvicorn worker with its heavy pool's processes), and per worker by process
kind in PSS, which sums a process tree without counting shared pages twice (its own,
its pool's, its Chromium's with the browser's whole tree, other: bench/soak_rss.py; a
pool process renewed in the window is reported apart, its warm-up not read as a leak). The same per kind *at rest*: from the sample taken just before each
export burst (the previous burst's images drawn, Chromium's garbage collected: a burst's
~130 MB swing read on a slope over 4.5 minutes moves it by a few MB/min either way, a
trough that climbs is a leak). Not a test: it measures.

The verdict (issue 36: ≤ 1 MB/min per worker over the second half) is read on each
worker's *whole tree* (itself, its pool's processes, its Chromium's tree, anything else it
started), in PSS and in anonymous PSS, three ways, all printed:

* cycle means: the mean of the samples in each full export cycle (from one burst to the
  next, BURST_EVERY s) whose start is in the window, and the slope of those means. A
  mean over a whole period holds every phase of the burst once, so it keeps a trend and
  drops the ~90-130 MB swing: it does not depend on where the window's ends fall in a
  burst, and it uses every sample. The reading the target is judged on.
* troughs: the samples taken just before each burst (the same phase each time; fewer
  points, so noisier).
* all samples: least squares through the window, bursts and all; shown because it is
  what was reported before, not judged on (its value moves by MB/min with the phase of
  the window's two ends).

Anonymous PSS (soak_rss.py: Pss_Anon + Pss_Shmem) is what a leak grows; PSS adds the
file-backed pages of libraries and of chromium's binary, whose share moves with other
processes on the machine (another engineer's browser tests), so a PSS slope that the
anonymous one does not share is the machine, not the server. Both are printed; neither is
dropped.
"""
from __future__ import annotations

import argparse
import json
import os
import random
import sys
import tempfile
import threading
import time
from collections import Counter
from pathlib import Path

import common  # first: puts the checkout on sys.path
import httpx
from tests.live import running_server

from app.server import WORKER_HEALTHCHECK_S
import soak_rss

SLIDER = [
    "/api/v1/figures/lobe?theta_i_deg={t}&alpha={a}",
    "/api/v1/figures/ndf?alpha={a}",
    "/api/v1/figures/g1?alpha={a}",
    "/api/v1/figures/albedo?alpha={a}",
    "/api/v1/figures/fresnel?f0={f}",
    "/api/v1/figures/lobe3d?alpha={a}&theta_i_deg={t}",
    "/api/v1/figures/g2?alpha={a}",
]
#: the worst cases that run in the heavy pool's processes (issue 36's heavy routes)
POOL_WORST = [
    ("GET", "/api/v1/export/model.csv?n_theta=91&n_phi=60&masking=smith_numeric"),
    ("GET", "/api/v1/figures/sphere_env?n=256&samples=16&environment=studio&model=principled&sheen=1"),
]
WORST = [
    ("GET", "/api/v1/albedo?n=257&tol=1e-7&alpha=1e-4&masking=smith_numeric&ndf=exp_power&p=0.25"),
    ("GET", "/api/v1/albedo?n=257&tol=1e-7&alpha=1e-4&alpha_y=1"),
    ("GET", "/api/v1/figures/lobe3d?n_theta=500&n_phi=500&masking=smith_numeric"),
    ("GET", "/api/v1/albedo?n=32&samples=65536&method=mc_uniform&masking=smith_numeric"),
    ("GET", "/api/v1/samples?n=200000&alpha=1e-4&alpha_y=1"),
    ("GET", "/api/v1/figures/sphere?n=500"),
    ("GET", "/api/v1/albedo?n=9&multiscatter=kulla_conty&ndf=student_t&gamma={g}"),
    ("POST", "/api/v1/eval"),
    *POOL_WORST,
]
#: the warm-up's rounds of the pool's worst cases, POOL_CLIENTS of each at a time,
#: POOL_PAUSE s apart: a pool process loads a model's compiled loops from its second job
#: of that model on, once the background compile is done (app/kernels: "asked for a second
#: time"), so each pool process must meet each pool case at least three times, the last
#: after the compile, before its size is its working size
POOL_ROUNDS, POOL_CLIENTS, POOL_PAUSE = 4, 4, 15.0
WORST_EVERY = 20.0
BURST_EVERY = 60.0
BURST = 20
SLIDER_CLIENTS = 3


def _post_body() -> bytes:
    import numpy as np
    from app.config import Settings
    n = Settings().max_batch
    rng = np.random.default_rng(1)
    return json.dumps({"masking": "smith_numeric",
                       "theta_i_deg": rng.uniform(0, 90, n).tolist(),
                       "theta_o_deg": rng.uniform(0, 90, n).tolist(),
                       "phi_i_deg": rng.uniform(-360, 360, n).tolist(),
                       "phi_o_deg": rng.uniform(-360, 360, n).tolist()}).encode()


class Recorder:
    def __init__(self):
        self.lock = threading.Lock()
        self.status: Counter = Counter()
        self.busy = 0
        self.cheap: dict[str, list[float]] = {"baseline": [], "mixed": []}
        self.worst: list[dict] = []
        self.exports: list[dict] = []
        self.errors: list[str] = []

    def count(self, r: httpx.Response, phase: str | None) -> None:
        with self.lock:
            if phase is not None:
                self.status[r.status_code] += 1
                if r.status_code == 503 and "retry-after" in r.headers:
                    self.busy += 1
                if r.status_code >= 500 and len(self.errors) < 20:
                    self.errors.append(f"{r.status_code} {r.request.method} {r.request.url}: {r.text[:200]}")


def _slider(url: str, rec: Recorder, phase: list, stop: threading.Event) -> None:
    rnd = random.Random(threading.get_ident())
    with httpx.Client(base_url=url, timeout=60) as c:
        while not stop.is_set():
            path = rnd.choice(SLIDER).format(a=f"{rnd.uniform(0.01, 1):.3f}",
                                             t=f"{rnd.uniform(0, 89):.1f}", f=f"{rnd.uniform(0.02, 0.9):.3f}")
            t0 = time.perf_counter()
            try:
                r = c.get(path)
            except httpx.HTTPError as exc:
                with rec.lock:
                    rec.errors.append(f"{type(exc).__name__} {path}")
                    rec.status["transport error"] += 1
                continue
            seconds = time.perf_counter() - t0
            p = phase[0]
            rec.count(r, None if p == "warmup" else p)
            if r.status_code == 200 and p in rec.cheap:
                with rec.lock:
                    rec.cheap[p].append(seconds)


def _worst(url: str, rec: Recorder, body: bytes, k: int, phase: str = "mixed",
           retries: int = 0) -> None:
    """One worst case; a 503 with Retry-After tried again up to ``retries`` times."""
    method, path = WORST[k % len(WORST)]
    path = path.format(g=f"{1.6 + 0.1 * (k // len(WORST)):.2f}")
    with httpx.Client(base_url=url, timeout=120) as c:
        for attempt in range(retries + 1):
            t0 = time.perf_counter()
            if method == "POST":
                r = c.post(path, content=body, headers={"content-type": "application/json"})
            else:
                r = c.get(path)
            seconds = time.perf_counter() - t0
            if not (r.status_code == 503 and "retry-after" in r.headers and attempt < retries):
                break
            time.sleep(float(r.headers["retry-after"]))
    rec.count(r, phase)
    with rec.lock:
        rec.worst.append({"request": f"{method} {path}", "status": r.status_code, "phase": phase,
                          "seconds": round(seconds, 2), "retry_after": r.headers.get("retry-after")})


def _warm_up(url: str, rec: Recorder, body: bytes) -> None:
    """Every worst case three times (three clients at a time, so that each worker likely
    meets each one) and one export burst; then the pool's cases in POOL_ROUNDS rounds."""
    def one_worker(offset: int) -> None:
        for k in range(len(WORST)):
            _worst(url, rec, body, (k + offset) % len(WORST), phase="warmup")
    workers = [threading.Thread(target=one_worker, args=(o,))
               for o in (0, len(WORST) // 3, 2 * len(WORST) // 3)]
    workers += [threading.Thread(target=_export, args=(url, rec, k, "warmup")) for k in range(BURST)]
    _run_all(workers)
    first = WORST.index(POOL_WORST[0])
    for round_ in range(POOL_ROUNDS):
        if round_:
            time.sleep(POOL_PAUSE)
        _run_all([threading.Thread(target=_worst, args=(url, rec, body, first + k % len(POOL_WORST)),
                                   kwargs={"phase": "warmup", "retries": 5})
                  for k in range(POOL_CLIENTS * len(POOL_WORST))])


def _run_all(threads: list[threading.Thread]) -> None:
    for t in threads:
        t.start()
    for t in threads:
        t.join(timeout=600)


def _slope_mb_per_min(samples: list[tuple[float, int]]) -> float | None:
    """Least-squares slope of RSS (bytes) against time (s), in MB per minute."""
    if len(samples) < 3:
        return None
    t = [x for x, _ in samples]
    b = [y / 2**20 for _, y in samples]
    tm, bm = sum(t) / len(t), sum(b) / len(b)
    var = sum((x - tm) ** 2 for x in t)
    return 60.0 * sum((x - tm) * (y - bm) for x, y in zip(t, b)) / var if var else None


def _per_worker_slopes(per_worker: list[tuple[float, list[int]]], total: float) -> list:
    """Each uvicorn worker's (with its pool's) RSS slope over the run's last 45 %: the
    mixed phase's second half, in MB/min."""
    late = [(t, mbs) for t, mbs in per_worker if t >= total * 0.55]
    width = min((len(m) for _, m in late), default=0)
    return [_slope_mb_per_min([(t, mbs[k] * 2**20) for t, mbs in late]) for k in range(width)]


def _kind_slopes(by_kind: list[tuple[float, dict]], total: float, field: int = 0) -> dict:
    """Each uvicorn worker's memory per process kind over the run's last 45 % (the mixed
    phase's second half): soak_rss.lives, a pool process's renewal (or a Chromium
    replaced: app/export/image.py) reported apart; PSS (``field`` 0) or anonymous PSS
    (soak_rss.ANON)."""
    workers = sorted({w for _, s in by_kind for w in s})
    return {n: {kind: soak_rss.lives([(t, s[w][kind][field], s[w][kind][1]) for t, s in by_kind
                                      if w in s], total * 0.55)
                for kind in soak_rss.KINDS}
            for n, w in enumerate(workers)}


def _tree(s: dict, field: int) -> int:
    """A worker's whole tree (every kind summed) from one soak_rss.sample entry: PSS
    (field 0) or anonymous PSS (soak_rss.ANON), bytes."""
    return sum(s[kind][field] for kind in soak_rss.KINDS)


def _cycle_means(points: list[tuple[float, float]], bursts: list[float]) -> list[tuple[float, float]]:
    """(mid-time, mean) of ``points`` over each full cycle [bursts[i], bursts[i + 1])."""
    out = []
    for a, b in zip(bursts, bursts[1:]):
        inside = [y for t, y in points if a <= t < b]
        if inside:
            out.append(((a + b) / 2, sum(inside) / len(inside)))
    return out


def _whole_tree_slopes(by_kind: list[tuple[float, dict]], at_rest: list[tuple[float, dict]],
                       bursts: list[float], since: float) -> dict:
    """Each worker's whole tree over the window from ``since`` (s): MB/min by cycle
    means (the verdict: see the module's docstring), troughs and all samples, in PSS and
    anonymous PSS, with how many points each slope had and the tree's MB at the end."""
    workers = sorted({w for _, s in by_kind for w in s})
    cycles = [b for b in bursts if b >= since]
    out = {}
    for n, w in enumerate(workers):
        row = {}
        for name, field in (("pss", 0), ("anon", soak_rss.ANON)):
            pts = [(t, _tree(s[w], field) / 2**20) for t, s in by_kind if w in s and t >= since]
            rest = [(t, _tree(s[w], field) / 2**20) for t, s in at_rest if w in s and t >= since]
            means = _cycle_means(pts, cycles)
            row[name] = {"cycles_mb_per_min": soak_rss.slope_mb_per_min(means), "cycles": len(means),
                         "cycle_means_mb": [round(m, 1) for _, m in means],
                         "troughs_mb_per_min": soak_rss.slope_mb_per_min(rest), "troughs": len(rest),
                         "all_mb_per_min": soak_rss.slope_mb_per_min(pts), "samples": len(pts),
                         "end_mb": round(pts[-1][1], 1) if pts else None}
        out[n] = row
    return out


def _kind_cycle_slopes(by_kind: list[tuple[float, dict]], at_rest: list[tuple[float, dict]],
                       bursts: list[float], since: float) -> dict:
    """Each worker's kinds over the window from ``since``: MB/min of anonymous PSS by
    cycle means and by troughs (the whole tree's two phase-free readings, kind by kind;
    a renewal inside the window is in them, as it is in the tree)."""
    workers = sorted({w for _, s in by_kind for w in s})
    cycles = [b for b in bursts if b >= since]
    out = {}
    for n, w in enumerate(workers):
        out[n] = {}
        for kind in soak_rss.KINDS:
            pts = [(t, s[w][kind][soak_rss.ANON] / 2**20) for t, s in by_kind if w in s and t >= since]
            rest = [(t, s[w][kind][soak_rss.ANON] / 2**20) for t, s in at_rest if w in s and t >= since]
            out[n][kind] = {"cycles_mb_per_min": soak_rss.slope_mb_per_min(_cycle_means(pts, cycles)),
                            "troughs_mb_per_min": soak_rss.slope_mb_per_min(rest),
                            "troughs_mb": [round(b, 1) for _, b in rest]}
    return out


def _tree_line(n: int, row: dict) -> str:
    def f(v):
        return "n/a" if v is None else f"{v:+.1f}"
    parts = []
    for name, label in (("pss", "PSS"), ("anon", "anonymous")):
        v = row[name]
        parts.append(f"{label} {f(v['cycles_mb_per_min'])} by {v['cycles']} cycle means "
                     f"(troughs {f(v['troughs_mb_per_min'])}, all {v['samples']} samples "
                     f"{f(v['all_mb_per_min'])}; {v['end_mb']} MB at the end)")
    return f"  worker {n}, whole tree, second half, MB/min: " + "; ".join(parts)


def _kind_line(n: int, kinds: dict) -> str:
    """One worker's kinds on one line: the slope of the life alive at the window's start
    (its age then), and any renewal with its newest process's size against the largest
    of those before it."""
    parts = []
    for kind, v in kinds.items():
        if not v["end_mb"]:
            continue
        slope = "n/a" if v["mb_per_min"] is None else f"{v['mb_per_min']:+.1f}"
        part = f"{kind} {slope} ({v['end_mb']:.0f} MB, age {v['age_s']} s"
        if v["renewals"]:
            part += f", lived {v['span_s']} s into the window"
        if v["renewals"]:
            part += (f"; {v['renewals']} renewed, the newest at {v['newest_end_mb']:.0f} MB "
                     f"vs {v['before_max_mb']:.0f} MB before")
        parts.append(part + ")")
    return f"  worker {n}, second half, MB/min per kind (PSS): " + "; ".join(parts)


def _export(url: str, rec: Recorder, k: int, phase: str = "mixed") -> None:
    """One PNG export by a client that honours Retry-After (at most 5 tries)."""
    path = f"/api/v1/figures/lobe.png?alpha={0.05 + 0.01 * (k % 90):.2f}&width=800&height=500"
    t0, tries = time.perf_counter(), 0
    with httpx.Client(base_url=url, timeout=120) as c:
        while True:
            tries += 1
            r = c.get(path)
            rec.count(r, phase)
            if r.status_code == 503 and "retry-after" in r.headers and tries < 5:
                time.sleep(float(r.headers["retry-after"]))
                continue
            break
    with rec.lock:
        rec.exports.append({"status": r.status_code, "tries": tries,
                            "seconds": round(time.perf_counter() - t0, 2)})


def _workers_rss(master: int) -> dict[int, int]:
    """Resident bytes of each of the master's child processes (the uvicorn workers, and
    multiprocessing's resource tracker): its own, and its direct children's, from /proc:
    its heavy pool's processes (app/work) and Chromium's launcher (choreographer's 15 MB
    wrapper, not the browser below it); soak_rss.sample has the whole tree by kind."""
    parent, rss = {}, {}
    for d in Path("/proc").iterdir():
        if not d.name.isdigit():
            continue
        try:
            stat = (d / "stat").read_text()
            parent[int(d.name)] = int(stat.rsplit(")", 1)[1].split()[1])
            for line in (d / "status").read_text().splitlines():
                if line.startswith("VmRSS:"):
                    rss[int(d.name)] = int(line.split()[1]) * 1024
        except (OSError, ValueError, IndexError):
            continue
    workers = [p for p, pp in parent.items() if pp == master]
    return {w: (rss.get(w, 0), sum(rss.get(c, 0) for c, pp in parent.items() if pp == w))
            for w in workers}


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--minutes", type=float, default=10.0)
    parser.add_argument("--json", action="store_true")
    parser.add_argument("--save", metavar="PATH", help="also write the JSON result (the RSS "
                        "samples included) to PATH")
    args = parser.parse_args()
    total = args.minutes * 60
    warmup, baseline = total * 0.1, total * 0.1
    body = _post_body()
    cache = tempfile.mkdtemp(prefix="brdf-soak-tables-")
    log_path = Path(tempfile.gettempdir()) / f"brdf-soak-{os.getpid()}.log"
    rec, phase, stop = Recorder(), ["warmup"], threading.Event()
    rss: list[tuple[float, str, int]] = []
    per_worker: list[tuple[float, list[int]]] = []     # (t, each worker's MB), every sample
    with_pool: list[tuple[float, list[int]]] = []      # the same, each with its pool's processes
    by_kind: list[tuple[float, dict]] = []             # (t, soak_rss.sample), every sample
    at_rest: list[tuple[float, dict]] = []             # the sample taken just before each burst
    bursts: list[float] = []                           # when each mixed-phase burst began (s)
    # stopped by the helper on the way out (SIGTERM, SIGKILL after 10 s)
    with running_server(("--workers", "2", "--timeout-worker-healthcheck", str(WORKER_HEALTHCHECK_S)),
                        env={"BRDF_CACHE_DIR": cache}, log_path=log_path, seconds=300) as (url, proc):
        common.log(f"soak: server up, {args.minutes:g} min, log {log_path}")
        clients = [threading.Thread(target=_slider, args=(url, rec, phase, stop), daemon=True)
                   for _ in range(SLIDER_CLIENTS)]
        for t in clients:
            t.start()
        t_start = time.monotonic()
        warming = threading.Thread(target=_warm_up, args=(url, rec, body), daemon=True)
        warming.start()
        while warming.is_alive() or time.monotonic() - t_start < warmup:
            rss.append((round(time.monotonic() - t_start, 1), "warmup", sum(map(sum, _workers_rss(proc.pid).values()))))
            by_kind.append((time.monotonic() - t_start, soak_rss.sample(proc.pid)))
            time.sleep(2.0)
        warmup = time.monotonic() - t_start          # the run is extended by a long warm-up
        total = warmup + 0.9 * args.minutes * 60
        common.log(f"soak: warm-up done after {warmup:.0f} s")
        side: list[threading.Thread] = []
        next_worst, next_burst, k_worst, k_export = warmup + baseline, warmup + baseline + 5, 0, 0
        while (now := time.monotonic() - t_start) < total:
            phase[0] = "baseline" if now < warmup + baseline else "mixed"
            workers = _workers_rss(proc.pid)
            by_kind.append((now, soak_rss.sample(proc.pid)))
            rss.append((round(now, 1), phase[0], sum(map(sum, workers.values()))))
            per_worker.append((round(now, 1), [round(v[0] / 2**20) for _, v in sorted(workers.items())]))
            with_pool.append((round(now, 1), [round(sum(v) / 2**20) for _, v in sorted(workers.items())]))
            if phase[0] == "mixed" and now >= next_worst:
                side.append(threading.Thread(target=_worst, args=(url, rec, body, k_worst), daemon=True))
                side[-1].start()
                k_worst, next_worst = k_worst + 1, next_worst + WORST_EVERY
            if phase[0] == "mixed" and now >= next_burst:
                at_rest.append(by_kind[-1])
                bursts.append(now)
                for _ in range(BURST):
                    side.append(threading.Thread(target=_export, args=(url, rec, k_export), daemon=True))
                    side[-1].start()
                    k_export += 1
                next_burst += BURST_EVERY
            time.sleep(2.0)
        stop.set()
        for t in clients + side:
            t.join(timeout=150)
    after_warmup = [b for t, p, b in rss if p != "warmup"]
    mixed = [(t, b) for t, p, b in rss if p == "mixed"]
    result = {
        "machine": common.machine(), "minutes": args.minutes,
        "status": {str(k): v for k, v in sorted(rec.status.items(), key=str)},
        "busy_503_with_retry_after": rec.busy,
        "5xx": sum(v for k, v in rec.status.items() if isinstance(k, int) and k >= 500),
        "5xx_other_than_busy": sum(v for k, v in rec.status.items()
                                   if isinstance(k, int) and k >= 500) - rec.busy,
        "cheap": {p: {"n": len(v), "p50_ms": 1e3 * common.percentile(v, 50),
                      "p99_ms": 1e3 * common.percentile(v, 99)} for p, v in rec.cheap.items()},
        "worst": rec.worst,
        "exports": {"n": len(rec.exports), "ok": sum(e["status"] == 200 for e in rec.exports),
                    "max_tries": max((e["tries"] for e in rec.exports), default=0),
                    "max_seconds": max((e["seconds"] for e in rec.exports), default=0)},
        "rss_mb": {"after_warmup": after_warmup[0] / 2**20 if after_warmup else None,
                   "end": after_warmup[-1] / 2**20 if after_warmup else None,
                   "max": max(after_warmup) / 2**20 if after_warmup else None,
                   "mixed_second_half_mb_per_min": _slope_mb_per_min(mixed[len(mixed) // 2:]),
                   "per_worker_second_half_mb_per_min": _per_worker_slopes(per_worker, total),
                   "with_pool_second_half_mb_per_min": _per_worker_slopes(with_pool, total),
                   "by_kind_second_half": _kind_slopes(by_kind, total),
                   "at_rest_second_half": _kind_slopes(at_rest, total),
                   "anon_by_kind_second_half": _kind_slopes(by_kind, total, soak_rss.ANON),
                   "whole_tree_second_half": _whole_tree_slopes(by_kind, at_rest, bursts, total * 0.55),
                   "anon_kind_cycles_second_half": _kind_cycle_slopes(by_kind, at_rest, bursts, total * 0.55),
                   "bursts_s": [round(b, 1) for b in bursts],
                   "warmup_s": round(warmup, 1),
                   "samples": [(t, round(b / 2**20)) for t, _, b in rss[::5]],
                   "per_worker": per_worker[::5],
                   "per_worker_by_kind": [(round(t), [[round(s[w][k][0] / 2**20) for k in soak_rss.KINDS]
                                                      for w in sorted(s)]) for t, s in by_kind[::5]],
                   "per_worker_by_kind_anon": [(round(t), [[round(s[w][k][soak_rss.ANON] / 2**20)
                                                            for k in soak_rss.KINDS] for w in sorted(s)])
                                               for t, s in by_kind]},
        "errors": rec.errors,
    }
    c = result["cheap"]
    result["cheap_p99_ratio"] = (c["mixed"]["p99_ms"] / c["baseline"]["p99_ms"]
                                 if c["baseline"]["n"] and c["mixed"]["n"] else None)
    if args.save:
        Path(args.save).write_text(json.dumps(result, indent=1))
    if args.json:
        print(json.dumps(result, indent=1))
        return
    print(f"statuses {result['status']}; 5xx {result['5xx']} "
          f"(busy 503 + Retry-After {rec.busy}, other {result['5xx_other_than_busy']})")
    for p, v in c.items():
        print(f"cheap {p:8s} n={v['n']:5d} p50 {v['p50_ms']:7.1f} ms p99 {v['p99_ms']:7.1f} ms")
    print(f"cheap p99 mixed/baseline: {result['cheap_p99_ratio']}")
    for w in rec.worst:
        print(f"worst {w['status']} {w['seconds']:6.2f} s {w['request'][:100]}")
    print(f"exports {result['exports']}")
    r = result["rss_mb"]
    print(f"workers' RSS: after warm-up ({r['warmup_s']:.0f} s) {r['after_warmup']:.0f} MB, end "
          f"{r['end']:.0f} MB, max {r['max']:.0f} MB; mixed phase's second half "
          f"{r['mixed_second_half_mb_per_min']:+.1f} MB/min; per process "
          f"{', '.join(f'{v:+.1f}' for v in r['per_worker_second_half_mb_per_min'] if v is not None)} MB/min, "
          f"with its pool's processes "
          f"{', '.join(f'{v:+.1f}' for v in r['with_pool_second_half_mb_per_min'] if v is not None)} MB/min")
    for n, row in r["whole_tree_second_half"].items():
        print(_tree_line(n, row))
    for n, kinds in r["by_kind_second_half"].items():
        print(_kind_line(n, kinds))
    for n, kinds in r["anon_by_kind_second_half"].items():
        print(_kind_line(n, kinds).replace("(PSS)", "(anonymous PSS)"))
    for n, kinds in r["anon_kind_cycles_second_half"].items():
        print(f"  worker {n}, second half, anonymous MB/min per kind by cycle means (troughs): " + "; ".join(
            f"{kind} {'n/a' if v['cycles_mb_per_min'] is None else format(v['cycles_mb_per_min'], '+.1f')} "
            f"({'n/a' if v['troughs_mb_per_min'] is None else format(v['troughs_mb_per_min'], '+.1f')}; "
            f"troughs {', '.join(f'{b:.0f}' for b in v['troughs_mb'])} MB)" for kind, v in kinds.items()))
    for n, kinds in r["at_rest_second_half"].items():
        print(_kind_line(n, kinds).replace("second half", "second half at rest (before each export burst)"))
    for e in rec.errors:
        print("error:", e)


if __name__ == "__main__":
    main()
