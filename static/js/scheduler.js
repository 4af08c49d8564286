/* Fetch and draw, at the speed of the hand.
 *
 * touch(panel) after every state change: a panel that is wanted (shown and in or near
 * the viewport) and whose request differs from what it drew fetches at once; all
 * panels touched by one change fetch together. At most one request per panel is in
 * flight: a change meanwhile marks it dirty, and the newest state is fetched as soon as
 * the answer lands (so a drag costs the server one request per panel at a time, and
 * every answer is newer than the last one drawn). Answers are drawn in animation
 * frames: at most one draw per panel per frame, the newest answer wins (an older one
 * waiting is dropped), and a frame stops drawing after FRAME_BUDGET_MS so that the
 * next input event is not kept waiting; the rest draw in the next frame.
 *
 * The panel supplies: wanted(), request() -> {key, url, init}, receive(req, res, body)
 * -> {retry: true} | drawable (throws an Error to show), draw(drawable) -> Promise,
 * fail(message).
 */
const FRAME_BUDGET_MS = 10;

export class Scheduler {
  constructor() {
    this.ready = new Map();      // panel -> {key, drawable | error}, in arrival order
    this.frame = 0;
    this.onIdle = () => {};
  }

  touch(panel) {
    if (!panel.wanted()) {
      if (panel.inflight) panel.inflight.ctrl.abort();
      panel.dirty = false;
      return;
    }
    const req = panel.request();
    if (panel.inflight) {
      panel.dirty = panel.inflight.key !== req.key;
      return;
    }
    const waiting = this.ready.get(panel);
    if ((waiting ? waiting.key : panel.drawnKey) === req.key) return;   // nothing it shows has changed
    this.fetch(panel, req);
  }

  async fetch(panel, req) {
    const ctrl = new AbortController();
    panel.inflight = { key: req.key, ctrl };
    panel.loading(true);
    let result;
    try {
      let res;
      try {
        res = await fetch(req.url, { ...req.init, signal: ctrl.signal });
      } catch (e) {
        if (ctrl.signal.aborted) return;
        throw new Error("Cannot reach the server.");
      }
      const body = await res.json().catch(() => null);
      if (ctrl.signal.aborted) return;
      const out = panel.receive(req, res, body);
      if (out.retry) panel.dirty = true;
      else result = { key: req.key, drawable: out };
    } catch (e) {
      if (!ctrl.signal.aborted) result = { key: req.key, error: e.message || String(e) };
    } finally {
      if (panel.inflight && panel.inflight.ctrl === ctrl) panel.inflight = null;
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
      if (!panel.inflight && !this.ready.has(panel)) panel.loading(false);
      this.checkIdle();
    }
  }

  /** A data-only redraw at once (Plotly draws it in its next animation frame, a newer
   * one replacing it); false when the answer needs a full draw in our frame. */
  quick(panel, r) {
    const p = panel.quick?.(r.drawable);
    if (!p) return false;
    panel.drawnKey = r.key;
    // a newer redraw interrupts this one: Plotly then rejects its promise, which is no error
    const a = p.catch(() => {}).finally(() => {
      if (panel.animating === a) panel.animating = null;
      if (this.ready.size) this.requestFrame();
      this.checkIdle();
    });
    panel.animating = a;
    return true;
  }

  requestFrame() {
    if (!this.frame) this.frame = requestAnimationFrame(() => this.draw());
  }

  draw() {
    this.frame = 0;
    const t0 = performance.now();
    for (const [panel, r] of [...this.ready]) {
      if (panel.drawing || panel.animating) continue;   // its last draw has not finished
      if (performance.now() - t0 > FRAME_BUDGET_MS) break;
      this.ready.delete(panel);
      if (r.error) {
        panel.fail(r.error);
        panel.drawnKey = r.key;
        continue;
      }
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
    return panels.filter((p) => p.inflight || p.dirty || p.drawing || p.animating || this.ready.has(p)).length;
  }

  checkIdle() {
    this.onIdle();
  }
}
