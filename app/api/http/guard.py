"""The request guard: refuse what no route should see (a query string too long, a
scalar parameter given twice, a number written as no client writes one, a body too large,
with both Content-Length and Transfer-Encoding, or not strict JSON (strict.py), a query
string sent to a body-only operation), list every method of a path in a 405, and open
the request's time budget (BRDF_MAX_SECONDS)."""
from __future__ import annotations

import asyncio
import json
import time
from collections import Counter, deque
from urllib.parse import parse_qsl

from fastapi import FastAPI
from starlette.concurrency import run_in_threadpool
from starlette.datastructures import Headers, MutableHeaders

from ...config import Settings
from ...integrate import budget
from ..openapi import operations
from . import content_types, strict

#: a JSON body up to this size is judged on the event loop: ~0.3 ms here (strict.parse_json
#: reads ~25 µs a KiB), less than the hop to a worker thread and back under load, which
#: a slider's POST /api/v1/batch (~1.5 KiB) paid on every move; a larger one is judged in
#: a worker thread (a 24 MB body took 5 s)
INLINE_JSON_BYTES = 8 * 1024


#: seconds of a body's arrival counted against the request's time budget: a 30 MB upload
#: took 0.6-0.8 s to arrive over loopback at load 16 (the server's own event loop reading
#: it), and its answer, cut at the budget counted from the body's end, came 11.1-11.3 s
#: after its first byte (bench/worst_heavy.py); a client slower than this sends in its own
#: time, or a slow link could never upload what a fast one can
BODY_COUNTED_SECONDS = 1.0
#: the setting of the seconds a request body may go without a byte (Settings.body_idle_seconds)
BODY_IDLE_ENV = "BRDF_BODY_IDLE_SECONDS"


def json_error(status: int, loc: list, msg: str, kind: str) -> tuple[dict, bytes]:
    """The start message and the body of an error the guard answers."""
    body = json.dumps({"detail": [{"loc": loc, "msg": msg, "type": kind}]}).encode()
    start = {"type": "http.response.start", "status": status,
             "headers": [(b"content-type", b"application/json"),
                         (b"content-length", str(len(body)).encode())]}
    return start, body


async def _send_error(send, status: int, loc: list, msg: str, kind: str,
                      close: bool = False) -> None:
    start, body = json_error(status, loc, msg, kind)
    if close:          # the rest of the body will not be read: end the connection
        start["headers"].append((b"connection", b"close"))
    await send(start)
    await send({"type": "http.response.body", "body": body})


def _replay(messages: list, receive):
    """A receive that hands out the buffered ``messages``, then asks the server's
    ``receive`` (a disconnect, say). Built outside the guard's call, with the server's
    receive as an argument: a closure there that called ``receive`` after rebinding that
    name to itself referred to itself (and recursed without end once the body was read).
    That cycle kept each buffered body (a full POST /eval batch: ~20 MB) alive until the
    cycle collector's oldest generation ran, which in a worker serving for minutes it
    seldom did: its resident memory stepped up ~20 MB a batch (docs/robustness.md §3).
    Without a cycle the body goes when the request ends; each message is let go as it
    is handed out (the route keeps its own copy of the body)."""
    replay = deque(messages)

    async def receive_buffered():
        return replay.popleft() if replay else await receive()
    return receive_buffered


def query_refusal(app: FastAPI, settings: Settings, path: str, method: str,
                  qs: bytes) -> strict.Refusal | None:
    """What the guard answers to this query string before any route runs, or None: too
    long (414), a query parameter sent to an operation that reads only a JSON body, a
    number written as no client writes one, a scalar parameter given twice (422).
    POST /api/v1/batch asks it of each of its entries, as their GETs would."""
    if len(qs) > settings.max_query_bytes:
        return strict.Refusal(414, ["query"], f"the query string has {len(qs)} bytes; the limit "
                              f"is {settings.max_query_bytes} (setting BRDF_MAX_QUERY_BYTES); "
                              "send long lists as a JSON body to POST /api/v1/eval",
                              "query_too_long")
    if not qs:
        return None
    op = operations(app).operation(path, method)
    pairs = parse_qsl(qs.decode("latin-1"), keep_blank_values=True)
    counts = Counter(k for k, _ in pairs)
    body_only = bool(op and "requestBody" in op
                     and not any(p.get("in") == "query" for p in op.get("parameters", [])))
    if counts and body_only:
        # POST /eval: a query parameter there would be ignored without a word
        k = next(iter(counts))
        return strict.Refusal(422, ["query", k], f"{k}: this endpoint takes its parameters "
                              "in the JSON body, not the query string", "extra_forbidden")
    try:
        strict.check_query(pairs, op)
    except strict.Refusal as r:
        return r
    twice = [k for k, c in counts.items() if c > 1 and op is not None and k not in _lists(op)]
    if twice:
        k = min(twice)
        return strict.Refusal(422, ["query", k], f"{k} given {counts[k]} times; give it once "
                              "(only list parameters may repeat)", "duplicate_parameter")
    return None


def _lists(op: dict) -> frozenset[str]:
    """The operation's query parameters that are arrays (and so may repeat)."""
    out = set()
    for p in op.get("parameters", []):
        schema = p.get("schema", {})
        variants = [schema, *schema.get("anyOf", []), *schema.get("oneOf", [])]
        if p.get("in") == "query" and any(v.get("type") == "array" for v in variants):
            out.add(p["name"])
    return frozenset(out)


class RequestGuard:
    """Refuse what no route should see, and open the request's time budget.

    A scalar query parameter given twice (``alpha=0.1&alpha=0.2``) is ambiguous — the
    framework would silently take the last — so it is a 422 naming the parameter. Which
    parameters are lists (and may repeat: ``theta_i_deg=10&theta_i_deg=20``) is read from
    the matched operation's parameters as the OpenAPI document lists them (indexed from
    the routes: openapi.route_document), so new endpoints are covered as they are added. For the same reason a query parameter sent to an operation that reads
    only a JSON body is refused rather than ignored.
    """

    def __init__(self, app, fastapi_app: FastAPI, settings: Settings):
        self.app = app
        self.fastapi_app = fastapi_app
        self.settings = settings
        self._numeric_names: frozenset[str] | None = None
        self.body_idle_seconds = settings.body_idle_seconds

    def _operation(self, scope) -> dict | None:
        return operations(self.fastapi_app).operation(scope["path"], scope["method"])

    async def __call__(self, scope, receive, send):
        if scope["type"] != "http":
            await self.app(scope, receive, send)
            return
        s = self.settings
        arrived = time.perf_counter()
        refusal = query_refusal(self.fastapi_app, s, scope["path"], scope["method"],
                                scope.get("query_string", b""))
        if refusal is not None:
            await _send_error(send, refusal.status, refusal.loc, refusal.message, refusal.kind)
            return
        wrong_type = content_types.refusal(self._operation(scope), scope["method"],
                                           scope["path"], Headers(scope=scope))
        if wrong_type is not None:
            await _send_error(send, wrong_type.status, wrong_type.loc, wrong_type.message,
                              wrong_type.kind)
            return
        limit_name = self._body_limit(scope)
        limit = getattr(s, limit_name)
        headers = Headers(scope=scope)
        length = headers.get("content-length")
        if length is not None and "transfer-encoding" in headers:
            # RFC 9112 6.1: a request with both is a smuggling vector; refused, not guessed
            await _send_error(send, 400, ["header", "transfer-encoding"],
                              "Content-Length and Transfer-Encoding together: send one",
                              "ambiguous_length")
            return
        if length is not None and length.isdigit() and int(length) > limit:
            await _send_error(send, 413, ["body"], self._body_message(int(length), limit_name),
                              "body_too_large")
            return
        judge = self._json_body(scope, headers)
        # when the request's clock starts: its arrival, or BODY_COUNTED_SECONDS before its
        # body's end for a body slower to arrive (each gap bounded by BRDF_BODY_IDLE_SECONDS);
        # the body's parsing here counts in full (a 256² LUT's JSON took 2.7 s to judge at
        # load 9 before the budget's clock started, and the answer came at 12.75 s)
        work_started = arrived
        if scope["method"] in ("POST", "PUT", "PATCH"):
            # Every body read here, up to the limit, before the route sees any of it (the
            # route's body reader would turn an error raised mid-stream into a vague 400),
            # each piece within BODY_IDLE_SECONDS of the last (a client that stops sending
            # would hold the worker's memory and a connection without end)
            messages, received = [], 0
            while True:
                try:
                    async with asyncio.timeout(self.body_idle_seconds):
                        message = await receive()
                except TimeoutError:
                    await _send_error(send, 408, ["body"], (
                        f"no byte of the request body for {self.body_idle_seconds:g} s after "
                        f"{received} bytes; the limit is setting {BODY_IDLE_ENV}"),
                        "body_timeout", close=True)
                    return
                messages.append(message)
                received += len(message.get("body", b""))
                if received > limit:
                    await _send_error(send, 413, ["body"], self._body_message(received, limit_name),
                                      "body_too_large")
                    return
                if message["type"] != "http.request" or not message.get("more_body", False):
                    break
            work_started = max(arrived, time.perf_counter() - BODY_COUNTED_SECONDS)
            if judge:
                body = b"".join(m.get("body", b"") for m in messages)
                try:
                    if len(body) <= INLINE_JSON_BYTES:
                        strict.parse_json(body, self._numeric(), s.max_batch)
                    else:
                        await run_in_threadpool(strict.parse_json, body, self._numeric(),
                                                s.max_batch)
                except strict.Refusal as r:
                    await _send_error(send, r.status, r.loc, r.message, r.kind)
                    return
            receive, messages, body = _replay(messages, receive), None, None

        started = False
        request_budget: budget.Budget | None = None

        async def send_fixed(message):
            nonlocal started
            if message["type"] == "http.response.start":
                started = True
                if request_budget is not None and request_budget.notes:
                    # cut short: say so, and let no cache keep this answer
                    headers = MutableHeaders(scope=message)
                    headers["x-time-budget"] = (
                        f"cut; {len(request_budget.notes)} computation(s) stopped early to "
                        f"end within BRDF_MAX_SECONDS={s.max_seconds:g}")
                    headers["cache-control"] = "no-store"
                methods = (operations(self.fastapi_app).methods(scope["path"])
                           if message["status"] == 405 else None)
                if methods:
                    # Starlette lists the methods of the first route of the path only
                    # (GET for /api/v1/eval, which also takes POST).
                    MutableHeaders(scope=message)["allow"] = ", ".join(methods)
            await send(message)

        with budget.limit(s.max_seconds) as request_budget:
            request_budget.start = work_started
            await self.app(scope, receive, send_fixed)

    def _json_body(self, scope, headers: Headers) -> bool:
        """A JSON body for an operation that reads one: judged (strict.py) before the route."""
        kinds = content_types.accepted(self._operation(scope), scope["method"], scope["path"])
        return "application/json" in kinds and content_types.media_type(headers) in (
            "application/json", "")

    def _numeric(self) -> frozenset[str]:
        if self._numeric_names is None:
            self._numeric_names = strict.numeric_names(operations(self.fastapi_app).document)
        return self._numeric_names

    def _body_limit(self, scope) -> str:
        """The Settings field that limits this operation's body: ``x-body-limit`` of the
        operation (an upload route's own limit), else ``max_body_bytes``."""
        op = self._operation(scope)
        name = op.get("x-body-limit") if op else None
        return name if isinstance(name, str) and hasattr(self.settings, name) else "max_body_bytes"

    def _body_message(self, size: int, limit_name: str) -> str:
        return (f"the request body has {size} bytes or more; the limit is "
                f"{getattr(self.settings, limit_name)} (setting BRDF_{limit_name.upper()})")
