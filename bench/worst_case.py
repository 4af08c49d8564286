"""The most expensive request of every endpoint the default limits allow, in-process:
status, wall and CPU seconds, peak memory, and what the time budget did. Also the albedo
cache and gzip.

    python bench/worst_case.py            # every case, budget off and on (~5 min)
    python bench/worst_case.py --quick    # the budgeted runs only
    python bench/worst_case.py --mix      # issue 36's mix against a real server (worst_mix.py)

Each case runs in a fresh process (peak RSS is per process and never goes down), once
with BRDF_MAX_SECONDS at 1e9 (the uncut worst case) and once at the default 10 s;
"request" memory is the process's peak during the request above its resident size just
before it. Under the default budget each case must end within BRDF_MAX_SECONDS + 1 s and
BRDF_MAX_REQUEST_BYTES (1 GiB): "within" or "OVER" says which.
"""
from __future__ import annotations

import argparse
import json
import subprocess
import sys
import time
import zlib

import common  # first: puts the checkout on sys.path

SN = "masking=smith_numeric"
#: name -> (method, url, body): the largest request of every endpoint the default limits
#: allow, with the costliest model options (the numeric Smith Λ, two lobes, Student-t).
CASES = {
    "GET /eval, BRDF_MAX_QUERY_LIST pairs": ("GET", "/api/v1/eval?" + SN + "&quantities=f&quantities=D"
                                            "&quantities=G2&quantities=F" + "".join(
                                                f"&theta_o_deg={k % 90}" for k in range(1000)), None),
    "POST /eval, BRDF_MAX_BATCH pairs, smith_numeric": ("POST", "/api/v1/eval", "eval"),
    "POST /eval, 24 MB body (above BRDF_MAX_BATCH)": ("POST", "/api/v1/eval", "big"),
    "lobe figure 4001, Student-t two lobes smith_numeric": (
        "GET", "/api/v1/figures/lobe?n=4001&ndf=student_t&alpha2=0.05&lobe_mix=0.5&" + SN, None),
    "ndf figure 4001, exp_power": ("GET", "/api/v1/figures/ndf?n=4001&ndf=exp_power&p=0.25", None),
    "g1 figure 4001, gtr smith_numeric": ("GET", "/api/v1/figures/g1?n=4001&ndf=gtr&gamma=0.5&" + SN, None),
    "fresnel figure 4001, conductor": ("GET", "/api/v1/figures/fresnel?n=4001&fresnel=conductor", None),
    "lobe3d figure 500x500, smith_numeric": ("GET", "/api/v1/figures/lobe3d?n_theta=500&n_phi=500&" + SN, None),
    "g2 figure 500x500, direction-correlated smith_numeric": (
        "GET", "/api/v1/figures/g2?n=500&g2=direction_correlated&" + SN, None),
    "sphere figure 500x500 px": ("GET", "/api/v1/figures/sphere?n=500&" + SN, None),
    "slice figure 500x500": ("GET", "/api/v1/figures/slice?n=500&" + SN, None),
    "albedo 257 mu, tol 1e-7, exp_power p=0.25 smith_numeric α=1e-4": (
        "GET", "/api/v1/albedo?n=257&tol=1e-7&alpha=1e-4&" + SN + "&ndf=exp_power&p=0.25", None),
    "albedo 257 mu, tol 1e-7, GGX 1e-4:1": ("GET", "/api/v1/albedo?n=257&tol=1e-7&alpha=1e-4&alpha_y=1", None),
    "albedo Monte Carlo 32 mu x 65536, smith_numeric": (
        "GET", "/api/v1/albedo?n=32&samples=65536&method=mc_uniform&" + SN, None),
    "albedo Kulla-Conty, Student-t (no table yet)": (
        "GET", "/api/v1/albedo?n=9&multiscatter=kulla_conty&ndf=student_t&gamma=1.77", None),
    "samples 200000, GGX 1e-4:1": ("GET", "/api/v1/samples?n=200000&alpha=1e-4&alpha_y=1", None),
    "tradeoff, max budget": ("GET", "/api/v1/tradeoff?max_budget=65536&" + SN, None),
    "advise, smith_numeric": ("GET", "/api/v1/advise?" + SN, None),
    "checks, gtr smith_numeric": ("GET", "/api/v1/checks?ndf=gtr&" + SN, None),
    "POST /figures/lobe3d, 8 models 500x500 (cannot be overlaid)": ("POST", "/api/v1/figures/lobe3d", "compare"),
}

CHILD = r"""
import json, resource, sys, time, warnings
warnings.simplefilter("ignore")
import numpy as np
from fastapi.testclient import TestClient
from app.config import Settings
from app.main import create_app

def rss():
    for line in open("/proc/self/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024

method, url, body_kind, seconds = sys.argv[1], sys.argv[2], sys.argv[3], float(sys.argv[4])
s = Settings(max_seconds=seconds)
c = TestClient(create_app(s), raise_server_exceptions=False)
c.get("/api/v1/figures/lobe?n=9")       # imports and the compiled path: not this case's cost
rng = np.random.default_rng(1)
body = None
if body_kind == "eval":
    n = s.max_batch
    body = json.dumps({"masking": "smith_numeric", "quantities": ["f", "D", "G2", "F"],
                       **{k: rng.uniform(0, 90, n).tolist() for k in
                          ("theta_i_deg", "theta_o_deg", "phi_i_deg", "phi_o_deg")}})
elif body_kind == "big":
    per = (s.max_body_bytes - 1000) // 4 // 20
    body = json.dumps({k: np.round(rng.uniform(0, 90, per), 14).tolist() for k in
                       ("theta_i_deg", "theta_o_deg", "phi_i_deg", "phi_o_deg")})
elif body_kind == "compare":
    body = json.dumps({"models": [{"ndf": n, "alpha": 0.1 + 0.1 * k, "masking": "smith_numeric"}
                                  for k, n in enumerate(["ggx", "beckmann", "student_t", "gtr",
                                                         "exp_power", "blinn_phong", "ggx", "beckmann"])],
                       "view": {"n_theta": 500, "n_phi": 500}})
before = rss()
t0, c0 = time.perf_counter(), time.process_time()
if method == "POST":
    r = c.post(url, content=body, headers={"content-type": "application/json"})
else:
    r = c.get(url)
out = {"status": r.status_code, "wall": time.perf_counter() - t0, "cpu": time.process_time() - c0,
       "peak_mb": resource.getrusage(resource.RUSAGE_SELF).ru_maxrss / 1024,
       "request_mb": max(0, resource.getrusage(resource.RUSAGE_SELF).ru_maxrss * 1024 - before) / 2**20,
       "bytes": len(r.content), "cut": r.headers.get("x-time-budget"),
       "retry_after": r.headers.get("retry-after")}
if r.status_code >= 400:
    out["detail"] = r.text[:160]
elif url.startswith("/api/v1/albedo"):
    j = r.json()
    out.update(evaluations=j["evaluations"], complete=j.get("complete"),
               max_E_error=max(e for e in j["E_error"] if e is not None))
print(json.dumps(out))
"""


def run_case(case: tuple, seconds: float) -> dict:
    method, url, body = case
    p = subprocess.run([sys.executable, "-c", CHILD, method, url, body or "-", str(seconds)],
                       cwd=common.ROOT, capture_output=True, text=True)
    if p.returncode:
        return {"status": "crashed", "wall": 0.0, "cpu": 0.0, "peak_mb": 0.0, "request_mb": 0.0,
                "detail": p.stderr.strip().splitlines()[-1][:200] if p.stderr.strip() else ""}
    return json.loads(p.stdout.strip().splitlines()[-1])


def albedo_cache() -> dict:
    """Miss (computed) against hit (served from the bounded cache), same request."""
    import warnings
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient
    from app.views import albedo as views
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


def seconds_of(key: str) -> bool:
    """Whether the case ran under the default budget (its limits are the ones checked)."""
    return "budget 10 s" in key


def main() -> None:
    if "--mix" in sys.argv:
        import worst_mix
        worst_mix.main([a for a in sys.argv[1:] if a != "--mix"])
        return
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--quick", action="store_true")
    parser.add_argument("--json", action="store_true")
    args = parser.parse_args()
    result = {"machine": common.machine() if hasattr(common, "machine") else {}, "cases": {}}
    for name, case in CASES.items():
        for seconds in ((10.0,) if args.quick else (1e9, 10.0)):
            key = f"{name} [budget {'off' if seconds > 1e6 else f'{seconds:g} s'}]"
            common.log(key)
            result["cases"][key] = r = run_case(case, seconds)
            common.log(f"  {r['status']} wall {r['wall']:.2f} s, request {r['request_mb']:.0f} MB")
    result["albedo_cache"] = albedo_cache()
    result["gzip_plotly_js"] = gzip_levels()
    if args.json:
        print(json.dumps(result, indent=1))
        return
    for key, r in result["cases"].items():
        extra = (f" evaluations={r['evaluations']:.3g} complete={r['complete']} "
                 f"max E_error={r['max_E_error']:.1e}" if "evaluations" in r else "")
        within = (r["wall"] <= 11.0 and r["request_mb"] * 2**20 <= 2**30) if seconds_of(key) else None
        print(f"{key:78s} {r['status']} wall {r['wall']:6.2f} s cpu {r['cpu']:6.2f} s "
              f"peak {r['peak_mb']:5.0f} MB (request {r['request_mb']:5.0f} MB)"
              f"{'' if within is None else ' within' if within else ' OVER'}{extra}"
              f"{' ' + r['detail'][:90] if r.get('detail') else ''}")
    for url, r in result["albedo_cache"].items():
        print(f"cache {url}: miss {r['miss_s'] * 1e3:.0f} ms, hit {r['hit_s'] * 1e3:.1f} ms")
    g = result["gzip_plotly_js"]
    print(f"plotly.min.js {g['identity_bytes']} B: " + ", ".join(
        f"{k} {v['bytes']} B in {v['seconds'] * 1e3:.0f} ms" for k, v in g.items() if k != "identity_bytes"))


if __name__ == "__main__":
    main()
