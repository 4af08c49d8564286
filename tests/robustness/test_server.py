"""``brdf-explorer serve --workers N``: connections get TCP_NODELAY (app/server.py).

uvicorn's multi-worker path bound the listening socket with proto 0 in older releases (0.55
passes IPPROTO_TCP), so asyncio left Nagle's algorithm on for accepted connections
and each keep-alive response waited ~40 ms for a delayed ACK (2 workers measured at 1/5
of 1 worker's throughput). The test serves the app from such a proto-0 socket, whatever
the installed uvicorn does, and reads the option off the server's side of a live
connection.
"""
from __future__ import annotations

import http.client
import os
import socket
import subprocess
import sys
import threading
import time
from pathlib import Path

import uvicorn

from app.server import HTTP_PROTOCOL

ROOT = Path(__file__).resolve().parents[2]


def test_connections_get_tcp_nodelay_on_a_socket_bound_like_the_workers_path():
    config = uvicorn.Config("app.main:app", host="127.0.0.1", port=0, http=HTTP_PROTOCOL,
                            log_level="warning", lifespan="off")
    listener = socket.socket(socket.AF_INET, socket.SOCK_STREAM)   # proto 0: asyncio skips it
    listener.bind(("127.0.0.1", 0))
    listener.set_inheritable(True)
    assert listener.proto == 0
    server = uvicorn.Server(config)
    thread = threading.Thread(target=server.run, kwargs={"sockets": [listener]}, daemon=True)
    thread.start()
    try:
        deadline = time.monotonic() + 30
        while not server.started and time.monotonic() < deadline:
            time.sleep(0.05)
        assert server.started
        conn = http.client.HTTPConnection("127.0.0.1", listener.getsockname()[1], timeout=10)
        conn.request("GET", "/api/v1/health")
        assert conn.getresponse().read()
        (protocol,) = server.server_state.connections
        sock = protocol.transport.get_extra_info("socket")
        assert sock.getsockopt(socket.IPPROTO_TCP, socket.TCP_NODELAY) != 0
        conn.close()
    finally:
        server.should_exit = True
        thread.join(timeout=10)
        listener.close()


_FREES = """
import sys, threading
import numpy as np
from app.allocator import return_large_frees_to_the_system
def rss():
    return int(open("/proc/self/statm").read().split()[1]) * 4096 / 2**20
print(return_large_frees_to_the_system())
base = rss()
def work(k):
    for i in range(30):                      # arrays of 4-52 MB, as large requests make
        a = np.ones((1 + (i * 7 + k) % 13) * 500_000)
        b = a * 2
        del a, b
threads = [threading.Thread(target=work, args=(k,)) for k in range(6)]
for t in threads:
    t.start()
for t in threads:
    t.join()
print(rss() - base)
"""


def test_a_worker_gives_large_arrays_back_after_a_request():
    """Six threads making and freeing arrays of 4-52 MB (what worst-case requests do in
    the thread pool): with glibc's defaults 366 MB stayed resident here (its mmap threshold
    rises after each large free, and each thread has its own heap); the soak's workers
    grew 608 → 1 278 MB. With the server's setting, what stays is under 16 MB."""
    out = subprocess.run([sys.executable, "-c", _FREES], cwd=ROOT, capture_output=True,
                         text=True, timeout=120, env={**os.environ, "PYTHONPATH": str(ROOT)})
    assert out.returncode == 0, out.stderr
    was_set, growth = out.stdout.split()
    assert was_set == "True"                  # glibc, as in Debian and the Docker image
    assert float(growth) < 16.0
