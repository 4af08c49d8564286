"""Resident memory of one server across full ``POST /api/v1/eval`` batches, and where a
batch's memory goes.

    python bench/eval_memory.py                  # uvicorn, 1 worker, 8 batches
    python bench/eval_memory.py --sliders 3      # the same with the soak's slider traffic
    python bench/eval_memory.py --stages         # in one process: each stage of a batch

The soak (bench/soak.py) saw one worker's RSS step up ~20 MB at each full batch
(250 000 pairs with ``smith_numeric``, a ~24 MB JSON body) and never come back. This
runs the same batch (the soak's body) against one uvicorn process, served as the soak
serves it, and reads its VmRSS after each; ``--sliders`` adds clients dragging the
soak's sliders meanwhile (their objects, allocated while a batch's are alive, are what
keeps a freed batch's allocator arenas resident). ``--stages`` runs a batch's stages in
this process, one by one, with tracemalloc's peak of each (tracemalloc's own tables
move the RSS, so none is read there). Not a test: it measures.
"""
from __future__ import annotations

import argparse
import gc
import json
import os
import subprocess
import sys
import tempfile
import threading
import time
import tracemalloc

import common  # first: puts the checkout on sys.path
import httpx

import soak


def _rss(pid: int | str = "self") -> int:
    for line in open(f"/proc/{pid}/status"):
        if line.startswith("VmRSS:"):
            return int(line.split()[1]) * 1024
    return 0


def served(batches: int, sliders: int) -> dict:
    """VmRSS of one uvicorn process after start, after a warm-up and after each batch."""
    port = common.free_port()
    url = f"http://127.0.0.1:{port}"
    env = {**os.environ, "PYTHONPATH": str(common.ROOT),
           "BRDF_CACHE_DIR": tempfile.mkdtemp(prefix="brdf-evalmem-")}
    proc = subprocess.Popen([sys.executable, "-m", "uvicorn", "--factory", "app.main:create_app",
                             "--host", "127.0.0.1", "--port", str(port), "--log-level", "warning"],
                            cwd=common.ROOT, env=env)
    body, mb, stop = soak._post_body(), lambda: round(_rss(proc.pid) / 2**20, 1), threading.Event()
    try:
        while True:
            try:
                if httpx.get(f"{url}/api/v1/health", timeout=2).status_code == 200:
                    break
            except httpx.HTTPError:
                time.sleep(0.5)
        rec = soak.Recorder()
        phase = ["baseline"]
        clients = [threading.Thread(target=soak._slider, args=(url, rec, phase, stop), daemon=True)
                   for _ in range(sliders)]
        for t in clients:
            t.start()
        out = {"started_mb": mb(), "sliders": sliders, "after_batch_mb": [], "seconds": []}
        with httpx.Client(base_url=url, timeout=300) as c:
            for k in range(batches + 1):
                t0 = time.perf_counter()
                r = c.post("/api/v1/eval", content=body, headers={"content-type": "application/json"})
                assert r.status_code == 200, r.text[:300]
                out["seconds"].append(round(time.perf_counter() - t0, 2))
                time.sleep(2.0)
                out["warm_mb" if k == 0 else "after_batch_mb"] = (
                    mb() if k == 0 else out["after_batch_mb"] + [mb()])
        stop.set()
        for t in clients:
            t.join(timeout=60)
        time.sleep(1.0)
        out["end_mb"] = mb()
        out["slider_requests"] = sum(rec.status.values())
        return out
    finally:
        stop.set()
        proc.terminate()
        proc.wait(timeout=20)


def stages() -> dict:
    """Each stage of a batch in this process, in the order the server runs them:
    tracemalloc's peak above the start of the stage (MB), and its seconds (traced)."""
    import warnings
    warnings.simplefilter("ignore")
    from fastapi.testclient import TestClient
    from app import quantities
    from app.api import encode
    from app.api.http import strict
    from app.config import Settings
    from app.main import create_app
    from app.views import schemas
    s = Settings()
    body = soak._post_body()
    with TestClient(create_app(s)) as c:        # the lifespan: allocator setting, loops
        c.post("/api/v1/eval", content=body, headers={"content-type": "application/json"})
        numeric = strict.numeric_names(c.app.openapi())
        out, held = {"body_mb": round(len(body) / 2**20, 1)}, {}

        def stage(name, fn):
            gc.collect()
            tracemalloc.start()
            t0 = time.perf_counter()
            held[name] = fn()
            _, peak = tracemalloc.get_traced_memory()
            tracemalloc.stop()
            out[name] = {"peak_mb": round(peak / 2**20, 1), "seconds": round(time.perf_counter() - t0, 2)}

        stage("strict_parse", lambda: strict.parse_json(body, numeric, s.max_batch))
        stage("json_loads", lambda: json.loads(body))
        payload = held["json_loads"]
        stage("validate", lambda: schemas.EvalQuery.model_validate(payload))
        q = held["validate"]

        def evaluate():
            import numpy as np
            a = {k: np.asarray(getattr(q, k), dtype=float)
                 for k in ("theta_i_deg", "phi_i_deg", "theta_o_deg", "phi_o_deg")}
            return quantities.evaluate(schemas.spec_of(q).brdf(), a["theta_i_deg"], a["phi_i_deg"],
                                       a["theta_o_deg"], a["phi_o_deg"], tuple(dict.fromkeys(q.quantities)))
        stage("evaluate", evaluate)
        stage("encode", lambda: encode.json_response(held["evaluate"]))
    return out


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--batches", type=int, default=8)
    parser.add_argument("--sliders", type=int, default=0, help="slider clients meanwhile")
    parser.add_argument("--stages", action="store_true")
    args = parser.parse_args()
    result = stages() if args.stages else served(args.batches, args.sliders)
    result["machine"] = common.machine()
    print(json.dumps(result, indent=1))


if __name__ == "__main__":
    main()
