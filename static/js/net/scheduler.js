/* Fetch and draw, at the speed of the hand.
 *
 * touch(panel) after every state change: a panel that is wanted (shown and in or near
 * the viewport) and whose request differs from what it drew fetches at once; all
 * panels touched by one change fetch together. At most MAX_IN_FLIGHT requests per panel
 * are in flight: a change beyond that marks it dirty, and the newest state is fetched as
 * soon as one lands (so a drag costs the server at most two requests per panel at a time,
 * the second sent while the first is answered: a round trip no longer halves the redraw
 * rate); an answer older than one already drawn or waiting is dropped when it lands. Answers are drawn
 * in animation frames: at most one draw per panel per frame, the newest answer wins (an
 * older one waiting is dropped), and a frame stops drawing after FRAME_BUDGET_MS so that
 * the next input event is not kept waiting; the rest draw in the next frame.
 *
 * Requests go through batch.js: the panels touched by one change ask in one request.
 *
 * A busy answer (503 with Retry-After: a table being built, a time budget spent on a
 * loaded machine) is not an error to show: the panel says it waits and asks again when
 * the server said, for the state as it is then; up to MAX_BUSY_TRIES times, after which
 * the server's message is shown as the error. A change meanwhile asks at once.
 *
 * A panel that leaves the viewport keeps its requests in flight (a scroll, or another panel
 * shown above it, is no reason to throw away an answer on its way); one hidden, or whose
 * view no longer takes the model, has them aborted.
 *
 * The panel supplies: wanted(), shows() (shown and taking the model, in view or not), request() -> {key, url, init}, batchable(req), receive(req, res, body)
 * -> {retry: true} | drawable (throws an Error to show), draw(drawable) -> Promise,
 * fail(message), busy(message).
 */
import { send } from "./batch.js";

const FRAME_BUDGET_MS = 10;
const MAX_IN_FLIGHT = 2;
// While a slider is held, requests go out at most every HELD_FRAME_MS (the newest state
// when the interval is up): at every input event, most answers would come to be dropped
// unseen, each having cost the page ~2 ms to send and read and the server ~8 ms of its
// 2 cores; 30 redraws a second is a smooth drag.
const HELD_FRAME_MS = 33;
// Busy answers in a row before the server's message is shown as the panel's error, and
// the longest wait taken from a Retry-After (a longer one is asked again sooner).
const MAX_BUSY_TRIES = 8;
const MAX_BUSY_WAIT_S = 30;

export class Scheduler {
  constructor() {
    this.ready = new Map();      // panel -> {key, drawable | error}, in arrival order
    this.frame = 0;
    this.flying = new Set();     // panels with a request in flight
    this.onIdle = () => {};
    this.held = () => false;     // a slider held: answers kept in memory may serve (batch.js)
    this.deferred = new Set();   // panels whose request waits for the held interval
    this.sentAt = -Infinity;     // when the last task's requests went out
    this.asking = false;         // a request went out in this task: others join it
    this.deferTimer = 0;
  }

  touch(panel) {
    panel.refiner?.check();           // a refinement at rest stops when its state is gone
    const flights = (panel.flights ||= []);
    if (!panel.wanted()) {
      this.unwait(panel);
      panel.dirty = false;
      // out of view only (scrolled away, or moved by another panel's change of size): what
      // it asked lands and is drawn; it asks for nothing new until it is back in view
      if (panel.shows?.()) return;
      for (const f of flights) f.ctrl.abort();
      flights.length = 0;
      panel.inflight = null;
      this.flying.delete(panel);
      return;
    }
    // waiting for the held interval: it asks then, for the state as it is by then (what
    // it would ask now is not worked out: half a drag's events come in the interval)
    if (this.deferred.has(panel)) return;
    const req = panel.request();
    if (panel.waiting) {
      if (panel.waiting.key === req.key) return;     // the server asked to wait: it asks then
      this.unwait(panel);                            // a new state: ask now
      panel.busyTries = 0;
    }
    if (flights.length) {
      panel.dirty = false;
      if (flights[flights.length - 1].key === req.key) return;     // asked already
      if (flights.length >= MAX_IN_FLIGHT) {
        panel.dirty = true;
        return;
      }
      if (!this.paced(panel)) this.fetch(panel, req);
      return;
    }
    const waiting = this.ready.get(panel);
    if ((waiting ? waiting.key : panel.drawnKey) === req.key) return;   // nothing it shows has changed
    if (!this.paced(panel)) this.fetch(panel, req);
  }

  /** While a slider is held, the page asks at most every HELD_FRAME_MS (the panels asking
   * in one task together, one batch); sooner, a panel waits (dirty) and asks for the
   * newest state with the others when the interval is up. */
  paced(panel) {
    const wait = HELD_FRAME_MS - (performance.now() - this.sentAt);
    if (!this.held() || this.asking || wait <= 0) return false;
    panel.dirty = true;
    this.deferred.add(panel);
    this.deferTimer ||= setTimeout(() => {
      this.deferTimer = 0;
      const due = [...this.deferred];
      this.deferred.clear();
      for (const p of due) {        // in one task: they still go out as one batch
        p.dirty = false;
        this.touch(p);
      }
    }, wait);
    return true;
  }

  async fetch(panel, req) {
    const ctrl = new AbortController();
    const flight = { key: req.key, ctrl, seq: (panel.seq = (panel.seq || 0) + 1), born: performance.now() };
    if (!this.asking) {                 // the first request of this task
      this.asking = true;
      this.sentAt = flight.born;
      queueMicrotask(() => { this.asking = false; });
    }
    panel.flights.push(flight);
    panel.inflight = flight;
    this.flying.add(panel);
    panel.loading(true);
    let result;
    try {
      let res, body;
      try {
        ({ res, body } = await send(req, ctrl.signal, { batchable: !!panel.batchable?.(req), recall: !!this.held?.() }));
      } catch (e) {
        if (ctrl.signal.aborted) return;
        throw new Error("Cannot reach the server.");
      }
      if (ctrl.signal.aborted || flight.seq < (panel.newestSeq || 0)) return;   // a newer answer is in
      if (res.retryAfter != null && panel.flights.some((f) => f.seq > flight.seq)) return;   // a newer request's answer will do
      if (res.retryAfter != null && (panel.busyTries || 0) < MAX_BUSY_TRIES) {
        panel.busyTries = (panel.busyTries || 0) + 1;
        this.wait(panel, req.key, res.retryAfter, body?.detail?.[0]?.msg);
        return;
      }
      panel.busyTries = 0;
      const out = panel.receive(req, res, body);
      if (out.retry) panel.dirty = true;
      else result = { key: req.key, seq: flight.seq, born: flight.born, drawable: out };
    } catch (e) {
      if (!ctrl.signal.aborted) result = { key: req.key, seq: flight.seq, error: e.message || String(e) };
    } finally {
      panel.flights = panel.flights.filter((f) => f !== flight);
      if (result) panel.newestSeq = result.seq;    // an older answer still to come is dropped
      panel.inflight = panel.flights[panel.flights.length - 1] || null;
      if (!panel.inflight) this.flying.delete(panel);
      if (result && !result.error && !panel.drawing && this.quick(panel, result)) {
        this.ready.delete(panel);          // an older answer waiting: this one is newer
      } else if (result) {
        this.ready.delete(panel);          // re-inserted last: arrival order
        this.ready.set(panel, result);
        this.requestFrame();
      }
      if (panel.dirty) {
        panel.dirty = false;
        this.touch(panel);
      }
      if (!panel.inflight && !this.ready.has(panel) && !panel.waiting) panel.loading(false);
      this.checkIdle();
    }
  }

  /** The server was busy: ask again for `key` in `seconds`, saying so meanwhile. */
  wait(panel, key, seconds, message) {
    this.unwait(panel);
    const s = Math.min(seconds, MAX_BUSY_WAIT_S);
    const timer = setTimeout(() => {
      panel.waiting = null;
      this.touch(panel);
      this.checkIdle();
    }, s * 1000);
    panel.waiting = { key, timer };
    panel.busy?.(`${message ? `${message.replace(/[:;,.]?\s*retry\.?$/i, "")} — ` : "The server is busy — "}asking again in ${Math.max(1, Math.round(s))} s…`);
  }

  unwait(panel) {
    if (!panel.waiting) return;
    clearTimeout(panel.waiting.timer);
    panel.waiting = null;
  }

  /** A curve panel's answer drawn by its chart at once (chart.js: at most once an
   * animation frame, the newest); false when the answer is drawn in our frame. */
  quick(panel, r) {
    const p = panel.quick?.(r.drawable);
    if (!p) return false;
    panel.drawnKey = r.key;
    const a = p.catch(() => {}).finally(() => {
      if (panel.framed === a) panel.framed = null;
      if (this.ready.size) this.requestFrame();
      this.checkIdle();
    });
    panel.framed = a;
    return true;
  }

  requestFrame() {
    if (!this.frame) this.frame = requestAnimationFrame(() => this.draw());
  }

  draw() {
    this.frame = 0;
    const t0 = performance.now();
    for (const [panel, r] of [...this.ready]) {
      if (panel.drawing || panel.framed) continue;   // its last draw has not finished
      if (performance.now() - t0 > FRAME_BUDGET_MS) break;
      this.ready.delete(panel);
      if (r.error) {
        panel.fail(r.error);
        panel.drawnKey = r.key;
        continue;
      }
      if (this.quick(panel, r)) continue;      // it came while a full draw ran: maybe data-only now
      panel.drawing = Promise.resolve(panel.draw(r.drawable))
        .catch((e) => panel.fail(e.message || String(e)))
        .finally(() => {
          panel.drawing = null;
          if (this.ready.size) this.requestFrame();
          this.checkIdle();
        });
      panel.drawnKey = r.key;
      if (!panel.inflight && !panel.dirty) panel.loading(false);
    }
    if (this.ready.size) this.requestFrame();
    this.checkIdle();
  }

  /** Requests in flight, answers waiting, draws under way (for tests and the bench). */
  pending(panels) {
    return panels.filter((p) => p.inflight || p.dirty || p.drawing || p.framed || p.waiting || this.ready.has(p)).length;
  }

  checkIdle() {
    this.onIdle();
  }
}
