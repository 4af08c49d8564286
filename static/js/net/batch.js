/* The panels' figure requests, one HTTP request a change.
 *
 * A slider move changes every panel in view: four GETs, each a fetch on the page's main
 * thread (~1.5–2 ms each, in the input handler), an exchange for the network service and
 * the server, and on a 2-core machine four server threads contending for the GIL beside
 * Chromium. The GETs of figures asked in one task go out together as one
 * POST /api/v1/batch (app/api/routes_batch.py), which answers each as its GET would:
 * status and JSON body, in order. A lone GET, a POST (pins) and a heavy image (which
 * would hold the curves back) go out as they are.
 *
 * Answers that a GET's Cache-Control lets a cache keep are kept here, and used while a
 * slider is held (`recall`): a drag back over the positions it just crossed draws from
 * memory, as it drew from the browser's HTTP cache when each figure was its own GET.
 * Any other change asks the server. A server without the batch route (404, 405) gets
 * plain GETs.
 *
 * A busy answer (503) carries the seconds its Retry-After asks to wait (`retryAfter`;
 * the batch gives it as the entry's `retry_after`).
 *
 * send(req, signal, {batchable, recall}) -> Promise<{res: {status, ok, statusText, retryAfter}, body}>;
 * rejects when the server cannot be reached or the signal aborted the request.
 */
import { API } from "../base/dom.js";

const BATCH_URL = `${API}/batch`;
const MAX_BATCH = 16;               // app/api/routes_batch.py MAX_REQUESTS
const MEMO_SIZE = 400;              // figures of a few KB each
const memo = new Map();             // url -> body (a JSON string), oldest first
let queue = [];
let batchOff = false;

const aborted = () => new DOMException("The request was aborted.", "AbortError");

function remember(url, cache, body) {
  if (!/max-age=[1-9]/.test(cache || "") || /no-store|no-cache|private/.test(cache)) return;
  memo.delete(url);
  memo.set(url, JSON.stringify(body));
  if (memo.size > MEMO_SIZE) memo.delete(memo.keys().next().value);
}

/** A kept answer: a fresh copy each time (the caller's drawing may modify its objects). */
function recall(url) {
  const text = memo.get(url);
  if (text === undefined) return null;
  memo.delete(url);                  // most recently used last
  memo.set(url, text);
  return { res: { status: 200, ok: true, statusText: "OK" }, body: JSON.parse(text) };
}

/** Seconds to wait before asking again, from a 503's Retry-After (null when none). */
function retryAfter(status, value) {
  const s = Number(value);
  return status === 503 && value !== null && value !== undefined && Number.isFinite(s) && s >= 0 ? s : null;
}

async function direct(req, signal) {
  const res = await fetch(req.url, { ...req.init, signal });
  const body = await res.json().catch(() => null);
  if (res.ok && !req.init?.method) remember(req.url, res.headers.get("Cache-Control"), body);
  return { res: { status: res.status, ok: res.ok, statusText: res.statusText,
                  retryAfter: retryAfter(res.status, res.headers.get("Retry-After")) }, body };
}

async function flush() {
  const items = queue.filter((x) => !x.signal.aborted);
  for (const x of queue) if (x.signal.aborted) x.reject(aborted());
  queue = [];
  for (let i = 0; i < items.length; i += MAX_BATCH) post(items.slice(i, i + MAX_BATCH));
}

async function post(items) {
  if (items.length === 1 || batchOff) {
    for (const x of items) direct(x.req, x.signal).then(x.resolve, x.reject);
    return;
  }
  let answer = null;
  try {
    const res = await fetch(BATCH_URL, { method: "POST", body: JSON.stringify({ requests: items.map((x) => x.req.url) }),
                                         headers: { Accept: "application/json", "Content-Type": "application/json" } });
    if (res.status === 404 || res.status === 405) batchOff = true;        // an older server
    if (res.ok) answer = await res.json().catch(() => null);
  } catch (e) {
    for (const x of items) x.reject(e);
    return;
  }
  const list = answer?.responses;
  if (!Array.isArray(list) || list.length !== items.length) {            // each on its own, then
    for (const x of items) direct(x.req, x.signal).then(x.resolve, x.reject);
    return;
  }
  items.forEach((x, i) => {
    const { status, cache, body, retry_after: wait } = list[i];
    const ok = status >= 200 && status < 300;
    if (ok) remember(x.req.url, cache, body);
    if (x.signal.aborted) x.reject(aborted());
    else x.resolve({ res: { status, ok, statusText: "", retryAfter: retryAfter(status, wait) }, body });
  });
}

export function send(req, signal, { batchable = false, recall: fromMemory = false } = {}) {
  if (fromMemory && !req.init?.method) {
    const kept = recall(req.url);
    if (kept) return Promise.resolve(kept);
  }
  if (!batchable) return direct(req, signal);
  return new Promise((resolve, reject) => {
    queue.push({ req, signal, resolve, reject });
    // every panel touched by this change asks in this task: send them when it ends
    if (queue.length === 1) queueMicrotask(flush);
  });
}
