"""Cold start: ``brdf-explorer serve`` in a clean clone, numba's cache empty, to the
default page fully drawn in headless Chromium (every visible panel drawn, nothing
pending: the same test as bench/slider.py's).

Each round clones the checkout's HEAD into a new temporary directory (so no compiled
loop, no numba cache, no table is there), starts the server from it, opens the page as
soon as the port accepts, and times serve → fully drawn. The browser is started before
the clock. Also reported: when the port first accepted, and the server's log lines that
say when the application was ready (the page's files are answered before: app/api/
startup.py) and which path answered (numpy until the compiled loops are ready).

    python bench/cold_start.py [rounds] [--empty-tables]

The E(μ, α) tables stay in the shared cache directory (~/.cache/brdf-explorer) unless
``--empty-tables``: then each round has its own empty one, as on a new machine (the
start-up queues the default tables' builds, and the albedo panel's first answer waits).
"""
from __future__ import annotations

import os
import signal
import socket
import subprocess
import sys
import tempfile
import time
from pathlib import Path

import common  # first: puts the checkout on sys.path

from slider import CHROMIUM, CHROMIUM_ARGS, QUIET_JS, VIEWPORT

DEADLINE_S = 60.0
#: the default page's panels, every one drawn (all are in view at VIEWPORT)
DEFAULT_PLOTS = ["plot-lobe", "plot-ndf", "plot-g1", "plot-albedo"]


def _free_port() -> int:
    with socket.socket() as s:
        s.bind(("127.0.0.1", 0))
        return s.getsockname()[1]


def _accepting(port: int) -> bool:
    with socket.socket() as s:
        s.settimeout(0.05)
        return s.connect_ex(("127.0.0.1", port)) == 0


def one_round(browser, workdir: Path, empty_tables: bool = False) -> dict:
    clone = workdir / "clone"
    subprocess.run(["git", "clone", "-q", "--no-hardlinks", str(common.ROOT), str(clone)], check=True)
    port = _free_port()
    env = {**os.environ, "PYTHONPATH": str(clone), "NUMBA_CACHE_DIR": str(workdir / "numba"),
           "PYTHONDONTWRITEBYTECODE": "1"}
    env.pop("BRDF_KERNEL_DIR", None)
    if empty_tables:
        env["XDG_CACHE_HOME"] = str(workdir / "cache")
        env.pop("BRDF_CACHE_DIR", None)
    log_path = workdir / "server.log"
    with open(log_path, "w") as log:
        t0 = time.perf_counter()
        # its own session: stopping it stops the compiler process it started, too
        server = subprocess.Popen([sys.executable, "-m", "app.cli", "serve", "--port", str(port)],
                                  cwd=clone, env=env, stdout=log, stderr=subprocess.STDOUT,
                                  start_new_session=True)
        try:
            while not _accepting(port):
                if time.perf_counter() - t0 > DEADLINE_S or server.poll() is not None:
                    raise RuntimeError(f"server did not accept: {log_path.read_text()[-2000:]}")
                time.sleep(0.02)
            t_accept = time.perf_counter() - t0
            page = browser.new_page(viewport=VIEWPORT)
            page.goto(f"http://127.0.0.1:{port}/", wait_until="domcontentloaded")
            page.wait_for_function(QUIET_JS, arg=DEFAULT_PLOTS, timeout=DEADLINE_S * 1000, polling=20)
            t_drawn = time.perf_counter() - t0
            page.close()
        finally:
            os.killpg(server.pid, signal.SIGTERM)
            try:
                server.wait(timeout=30)
            except subprocess.TimeoutExpired:
                os.killpg(server.pid, signal.SIGKILL)
                server.wait()
    lines = [ln for ln in log_path.read_text().splitlines()
             if "compiled loops" in ln or "numpy path" in ln or "application ready" in ln]
    return {"accept_s": t_accept, "drawn_s": t_drawn, "log": lines}


def run(rounds: int = 3, empty_tables: bool = False) -> dict:
    from playwright.sync_api import sync_playwright
    results = []
    with sync_playwright() as p:
        browser = p.chromium.launch(executable_path=CHROMIUM, args=CHROMIUM_ARGS)
        try:
            for k in range(rounds):
                with tempfile.TemporaryDirectory(prefix="brdf-cold-") as tmp:
                    r = one_round(browser, Path(tmp), empty_tables)
                common.log(f"  round {k + 1}: port accepts at {r['accept_s']:.2f} s, page drawn at "
                           f"{r['drawn_s']:.2f} s")
                results.append(r)
        finally:
            browser.close()
    drawn = [r["drawn_s"] for r in results]
    return {"cold_start_rounds": rounds, "cold_start_empty_tables": empty_tables,
            "cold_start_drawn_s": drawn,
            "cold_start_drawn_s_median": common.median(drawn),
            "cold_start_accept_s_median": common.median([r["accept_s"] for r in results]),
            "cold_start_loadavg": common.loadavg(), "cold_start_log_first_round": results[0]["log"]}


def report(r: dict) -> list[str]:
    tables = ", empty table cache" if r.get("cold_start_empty_tables") else ""
    return [f"cold start (clean clone, empty numba cache{tables}), serve → default page fully drawn: "
            f"median {r['cold_start_drawn_s_median']:.2f} s over {r['cold_start_rounds']} rounds "
            f"({', '.join(f'{x:.2f}' for x in r['cold_start_drawn_s'])}); port accepting at "
            f"{r['cold_start_accept_s_median']:.2f} s; load average {r['cold_start_loadavg']}",
            "  server log (first round):", *("    " + ln for ln in r["cold_start_log_first_round"])]


if __name__ == "__main__":
    args = [a for a in sys.argv[1:] if a != "--empty-tables"]
    result = run(int(args[0]) if args else 3, "--empty-tables" in sys.argv[1:])
    print("\n".join(report(result)))
