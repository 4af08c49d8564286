"""API latency per endpoint, warm, on 127.0.0.1: the real app in a uvicorn process on a
free port, an httpx client in this process (keep-alive, gzip accepted as a browser does).

Each endpoint is requested at the page's default sizes (lobe/ndf/g1 n = 181, lobe3d
46 × 91, albedo n = 17) — the figure routes the page fetches and the data routes
beside them — round-robin, so that load changes hit all alike. α changes on every
request (0.3 × (1 + 1e-4 k)), as it does under a slider: no two requests are the same,
so no cache on the server can answer them; the albedo route is also timed repeating
one request (``albedo_repeat``), which a server-side cache may answer.
"""
from __future__ import annotations

import time

import common  # first: puts the checkout on sys.path

import httpx

# (key, path, extra query) at the page's defaults.
ENDPOINTS = [
    ("lobe", "/api/v1/lobe", {"theta_i_deg": 45, "n": 181}),
    ("ndf", "/api/v1/ndf", {"n": 181}),
    ("g1", "/api/v1/g1", {"n": 181}),
    ("lobe3d", "/api/v1/lobe3d", {"theta_i_deg": 45, "n_theta": 46, "n_phi": 91}),
    ("albedo", "/api/v1/albedo", {"n": 17}),
    ("figures_lobe", "/api/v1/figures/lobe", {"theta_i_deg": 45}),
    ("figures_ndf", "/api/v1/figures/ndf", {}),
    ("figures_g1", "/api/v1/figures/g1", {}),
    ("figures_lobe3d", "/api/v1/figures/lobe3d", {"theta_i_deg": 45}),
    ("figures_albedo", "/api/v1/figures/albedo", {}),
]


def measure(url: str, rounds: int, warmup: int = 3) -> dict:
    out: dict = {}
    times = {key: [] for key, _, _ in ENDPOINTS}
    sizes: dict = {}
    with httpx.Client(base_url=url, timeout=60, headers={"Accept-Encoding": "gzip"}) as client:
        k = 0
        for r in range(warmup + rounds):
            for key, path, extra in ENDPOINTS:
                k += 1
                params = {"ndf": "ggx", "alpha": 0.3 * (1 + 1e-4 * k), **extra}
                t0 = time.perf_counter()
                res = client.get(path, params=params)
                body = res.content
                dt = time.perf_counter() - t0
                if res.status_code != 200:
                    raise RuntimeError(f"{path}: HTTP {res.status_code} {body[:200]!r}")
                if r >= warmup:
                    times[key].append(dt)
                sizes[key] = (int(res.headers.get("content-length", len(res.content))),
                              len(body), res.headers.get("content-encoding", "identity"))
        # one albedo request repeated (what a cache on the server would answer)
        repeat = []
        for r in range(warmup + rounds):
            t0 = time.perf_counter()
            client.get("/api/v1/figures/albedo", params={"ndf": "ggx", "alpha": 0.3}).raise_for_status()
            if r >= warmup:
                repeat.append(time.perf_counter() - t0)
        times["albedo_repeat"] = repeat
    for key, ts in times.items():
        ms = [1e3 * t for t in ts]
        out[f"latency_{key}_p50_ms"] = common.percentile(ms, 50)
        out[f"latency_{key}_p95_ms"] = common.percentile(ms, 95)
    for key, (wire, decoded, enc) in sizes.items():
        out[f"bytes_{key}"] = decoded
        out[f"bytes_{key}_wire"] = wire
        out[f"encoding_{key}"] = enc
    out["latency_rounds"] = rounds
    return out


def run(quick: bool = False) -> dict:
    rounds = 15 if quick else 60
    with common.server() as url:
        common.log(f"  server {url}; {len(ENDPOINTS)} endpoints x {rounds} rounds ...")
        load = common.loadavg()
        out = measure(url, rounds)
        out["latency_loadavg"] = [load, common.loadavg()]
        return out


def report(r: dict) -> list[str]:
    lines = [f"API latency, warm, 127.0.0.1 ({r['latency_rounds']} requests each; load average "
             f"{r['latency_loadavg'][0]} → {r['latency_loadavg'][1]}): p50 / p95 ms, body bytes (wire)"]
    for key, _, _ in ENDPOINTS:
        lines.append(f"  {key:16s} {r[f'latency_{key}_p50_ms']:7.1f} / {r[f'latency_{key}_p95_ms']:7.1f}"
                     f"   {r[f'bytes_{key}']:>8,} ({r[f'bytes_{key}_wire']:,} {r[f'encoding_{key}']})")
    lines.append(f"  {'albedo_repeat':16s} {r['latency_albedo_repeat_p50_ms']:7.1f} / "
                 f"{r['latency_albedo_repeat_p95_ms']:7.1f}   (the same request again)")
    return lines


if __name__ == "__main__":
    print("\n".join(report(run(quick=True))))
