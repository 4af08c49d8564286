/* A panel's readouts while a slider is held: the numbers in its heading and legend
 * (GGX α=0.0425, E_avg = 0.0488) are written at most every READOUT_MS, the newest value,
 * and at once when the slider is let go. The curves and the axes' labels follow every
 * held frame; the readouts beside them cannot be read at 30 changes a second (an
 * instrument's display updates a few times a second for that reason), and each rewrite
 * of a heading laid out the whole page: written with every held frame, they cost the
 * drag 10–15 % of its CPU (BENCHMARKS.md §5).
 */
export const READOUT_MS = 250;

export class Readouts {
  constructor() {
    this.pending = new Map();   // key -> write(), the newest for each readout
    this.at = -Infinity;        // when they were last written
    this.timer = 0;
  }

  /** Shows a readout: write() now, or while `held` once READOUT_MS have passed since
   * the last writing (a newer write of the same key replaces one waiting). */
  show(key, write, held) {
    this.pending.set(key, write);
    const wait = held ? this.at + READOUT_MS - performance.now() : 0;
    if (wait <= 0) this.flush();
    else this.timer ||= setTimeout(() => this.flush(), wait);
  }

  /** Forgets a waiting write: what it would show was drawn since (a full Plotly draw). */
  drop(key) {
    this.pending.delete(key);
  }

  /** Writes what waits, now (the slider let go). */
  flush() {
    clearTimeout(this.timer);
    this.timer = 0;
    this.at = performance.now();
    const writes = [...this.pending.values()];
    this.pending.clear();
    for (const write of writes) write();
  }
}
