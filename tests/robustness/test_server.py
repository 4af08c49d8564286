"""``brdf-explorer serve --workers N``: connections get TCP_NODELAY (app/server.py).

uvicorn's multi-worker path binds the listening socket with proto 0, so asyncio leaves
Nagle's algorithm on for accepted connections and each keep-alive response waits ~40 ms
for a delayed ACK (2 workers measured at 1/5 of 1 worker's throughput). The test serves
the app from exactly such a socket — uvicorn's own ``Config.bind_socket()`` — and reads
the option off the server's side of a live connection.
"""
from __future__ import annotations

import http.client
import socket
import threading
import time

import uvicorn

from app.server import HTTP_PROTOCOL


def test_connections_get_tcp_nodelay_on_a_socket_bound_like_the_workers_path():
    config = uvicorn.Config("app.main:app", host="127.0.0.1", port=0, http=HTTP_PROTOCOL,
                            log_level="warning", lifespan="off")
    listener = config.bind_socket()
    assert listener.proto == 0                    # the condition under which asyncio skips it
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
