"""The most expensive requests the default limits allow, in-process: wall and CPU
seconds, peak memory, and what the time budget did. Also the albedo cache and gzip.

    python bench/worst_case.py            # every case, budget off and on (~2 min)
    python bench/worst_case.py --quick    # the budgeted runs only

Each case runs in a fresh process (peak RSS is per process and never goes down), once
with BRDF_MAX_SECONDS at 1e9 (the uncut worst case) and once at the default 10 s.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
import zlib

import common  # first: puts the checkout on sys.path

CASES = {
    "albedo 257 mu, tol 1e-7, GGX 1e-4:1": "/api/v1/albedo?n=257&tol=1e-7&alpha=1e-4&alpha_y=1",
    "albedo 257 mu, tol 1e-7, Beckmann 1:1e-4": "/api/v1/albedo?n=257&tol=1e-7&alpha=1&alpha_y=1e-4&ndf=beckmann",
    "albedo 257 mu, tol 1e-7, isotropic GGX 0.3": "/api/v1/albedo?n=257&tol=1e-7",
    "lobe3d figure 500x500": "/api/v1/figures/lobe3d?n_theta=500&n_phi=500",
    "sphere figure 500x500 px": "/api/v1/figures/sphere?n=500",
    "slice figure 500x500": "/api/v1/figures/slice?n=500",
    "samples 200000, GGX 1e-4:1": "/api/v1/samples?n=200000&alpha=1e-4&alpha_y=1",
    "POST /eval, BRDF_MAX_BATCH pairs": "POST",
}

CHILD = r"""
import json, resource, sys, time, warnings
warnings.simplefilter("ignore")
import numpy as np
from fastapi.testclient import TestClient
from app.config import Settings
from app.main import create_app
url, seconds = sys.argv[1], float(sys.argv[2])
c = TestClient(create_app(Settings(max_seconds=seconds)))
if url == "POST":
    # four full lists of full-precision numbers, as long as the limit allows
    n = Settings().max_batch
    rng = np.random.default_rng(1)
    body = json.dumps({"theta_i_deg": rng.uniform(0, 90, n).tolist(),
                       "theta_o_deg": rng.uniform(0, 90, n).tolist(),
                       "phi_i_deg": rng.uniform(-360, 360, n).tolist(),
                       "phi_o_deg": rng.uniform(-360, 360, n).tolist()})
    t0, c0 = time.perf_counter(), time.process_time()
    r = c.post("/api/v1/eval", content=body, headers={"content-type": "application/json"})
else:
    t0, c0 = time.perf_counter(), time.process_time()
    r = c.get(url)
out = {"status": r.status_code, "wall": time.perf_counter() - t0, "cpu": time.process_time() - c0,
       "rss_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
       "bytes": len(r.content), "cut": r.headers.get("x-time-budget")}
if url.startswith("/api/v1/albedo"):
    j = r.json()
    out.update(evaluations=j["evaluations"], complete=j.get("complete"),
               max_E_error=max(e for e in j["E_error"] if e is not None))
print(json.dumps(out))
"""


def run_case(url: str, seconds: float) -> dict:
    p = subprocess.run([sys.executable, "-c", CHILD, url, str(seconds)], cwd=common.ROOT,
                       capture_output=True, text=True, check=True)
    return json.loads(p.stdout.strip().splitlines()[-1])


def albedo_cache() -> dict:
    """Miss (computed) against hit (served from the bounded cache), same request."""
    import warnings
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient
    from app.api import views
    from app.config import Settings
    from app.main import create_app
    c = TestClient(create_app(Settings()))
    c.get("/api/v1/figures/albedo?alpha=0.7")      # imports, JIT, tables: not a miss's cost
    out = {}
    for url in ("/api/v1/figures/albedo?alpha=0.2", "/api/v1/albedo?alpha=0.05&alpha_y=0.5"):
        views._albedo_cached.cache_clear()
        t0 = time.perf_counter()
        c.get(url)
        miss = time.perf_counter() - t0
        hits = []
        for _ in range(5):
            t0 = time.perf_counter()
            c.get(url)
            hits.append(time.perf_counter() - t0)
        out[url] = {"miss_s": miss, "hit_s": common.median(hits)}
    return out


def gzip_levels() -> dict:
    """The largest static file at each zlib level: size and seconds."""
    from app.main import PLOTLY_JS
    data = PLOTLY_JS.read_bytes()
    out = {"identity_bytes": len(data)}
    for level in (1, 6, 9):
        t0 = time.perf_counter()
        c = zlib.compressobj(level, zlib.DEFLATED, 16 + zlib.MAX_WBITS)
        size = len(c.compress(data) + c.flush())
        out[f"level {level}"] = {"bytes": size, "seconds": time.perf_counter() - t0}
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    result = {"machine": common.machine() if hasattr(common, "machine") else {}, "cases": {}}
    for name, url in CASES.items():
        for seconds in ((10.0,) if args.quick else (1e9, 10.0)):
            key = f"{name} [budget {'off' if seconds > 1e6 else f'{seconds:g} s'}]"
            common.log(key)
            result["cases"][key] = run_case(url, seconds)
    result["albedo_cache"] = albedo_cache()
    result["gzip_plotly_js"] = gzip_levels()
    if args.json:
        print(json.dumps(result, indent=1))
        return
    for key, r in result["cases"].items():
        extra = (f" evaluations={r['evaluations']:.3g} complete={r['complete']} "
                 f"max E_error={r['max_E_error']:.1e}" if "evaluations" in r else "")
        print(f"{key:60s} {r['status']} wall {r['wall']:6.2f} s cpu {r['cpu']:6.2f} s "
              f"peak {r['rss_mb']:6.0f} MB{extra}")
    for url, r in result["albedo_cache"].items():
        print(f"cache {url}: miss {r['miss_s'] * 1e3:.0f} ms, hit {r['hit_s'] * 1e3:.1f} ms")
    g = result["gzip_plotly_js"]
    print(f"plotly.min.js {g['identity_bytes']} B: " + ", ".join(
        f"{k} {v['bytes']} B in {v['seconds'] * 1e3:.0f} ms" for k, v in g.items() if k != "identity_bytes"))


if __name__ == "__main__":
    main()
