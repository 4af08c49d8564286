/* The environment sphere refined at rest (issue 34). Once the panel has drawn its figure
 * for the current state and no slider is held, it asks the data route for independent
 * renders of that same state (other seeds), averages them pixel by pixel (average.js) and
 * draws the average through the panel's one draw path (Panel.draw: the server's figure
 * with its image replaced, the heading's noise and samples restated), until the stated
 * noise is at most TARGET_NOISE. The first figure's own render (the view's 16 samples) is
 * not among them: renders of equal samples average with equal weights. A change of
 * state, a held slider or the panel leaving the page stops it; the next rest starts over
 * from one render.
 */
import { API, query } from "../base/dom.js";
import { ctx } from "../base/ctx.js";
import { fieldRole } from "../state/views.js";
import { RenderAverage } from "./average.js";

/** The stated relative noise at which the refinement stops: a slide's sphere. */
export const TARGET_NOISE = 0.05;
/** Samples per pixel of each refining render. At n = 256 under the studio (the default
 * model; 2 shared cores at load ~12) renders of 128 reach 5 % in 82 s (11 renders), of 64
 * in 92 s (22; bench/sphere_refine.py); 256 are refused at n = 256 (n²·samples above
 * BRDF_MAX_GRID_POINTS × 64) and took 19 s a render, past the request budget
 * (BRDF_MAX_SECONDS = 10). One render at a time, so that the one heavy worker
 * (app/work) is at most a render away from the next change's figure. A refusal on the
 * budget (413) halves it. */
export const REST_SAMPLES = 128;
/** The fewest a refusal on the budget halves the samples to (the view's own floor is 4). */
const MIN_SAMPLES = 16;
/** Quiet after a draw before the first refining request: a hand that moves on within it
 * costs the server no render. */
const REST_DELAY_MS = 300;
/** Longest wait, in seconds, between asks of a server that keeps answering "busy"
 * (503): each wait is its Retry-After, doubled per busy answer in a row up to this.
 * The refinement does not give up on a busy server (it stopped after three, and the
 * heading went on stating the noise of an average that would never improve): a render
 * asked this rarely costs a loaded server nothing. */
const MAX_BUSY_WAIT_S = 30;
/** The largest seed the view takes (2³¹ − 1): the renders' seeds wrap below it. */
const MAX_SEED = 2 ** 31 - 1;

/** The panel's statement of its noise and the samples it comes from, put before the
 * heading's model and lighting, which a narrow panel cuts off at two lines: "noise ±4.9%
 * at 1536 samples/pixel (12 × 128)". The noise is the RMS of the pixels' standard errors
 * over the mean (app/figures/sphere_image.py's caption, which the figure's title holds). */
export function samplingNote(noise, samples, renders = 1, perRender = samples) {
  return `noise ±${(100 * noise).toFixed(1)}% at ${samples} samples/pixel${renders > 1 ? ` (${renders} × ${perRender})` : ""}`;
}

/** The server's caption ("16 samples/pixel, noise ±47.2% (RMS …)") as samplingNote
 * states it; another text (a point light's "no sampling") as it is, without markup. */
export function serverNote(caption) {
  const text = caption.replace(/<[^>]*>/g, "");
  const m = text.match(/^(\d+) samples\/pixel, noise ±([\d.]+)%/);
  return m ? `noise ±${m[2]}% at ${m[1]} samples/pixel` : text;
}

export class Refiner {
  constructor(panel) {
    this.panel = panel;
    this.run = null;         // the refinement under way: {key}
    this.timer = 0;
    this.own = false;        // the panel is drawing one of ours
    this.finished = null;    // the key whose refinement reached TARGET_NOISE
    /** What the panel shows of it, for readers (tests): renders, samples, noise, done. */
    this.status = { key: null, renders: 0, samples: 0, noise: null, done: false, seeds: [] };
  }

  /** The panel drew a figure (Panel.draw): the scheduler's, a new one to refine at rest. */
  drawn(drawable) {
    if (this.own) return;
    this.stop();
    this.figure = drawable;
    this.finished = null;
    this.settle();
  }

  /** The page moved (the scheduler touched the panel, a slider was grabbed): a
   * refinement whose state is gone stops; at rest, one not yet done starts. */
  check() {
    if (this.run && !this.current(this.run.key)) this.stop();
    else if (!this.run) this.settle();
  }

  /** The panel shows the figure of the state as it is, at rest. */
  current(key) {
    const p = this.panel;
    return !ctx.held && p.wanted() && !p.error && p.drawnKey === key && p.request().key === key;
  }

  settle() {
    clearTimeout(this.timer);
    this.timer = setTimeout(() => {
      const key = this.panel.drawnKey;
      if (this.run || !this.figure || key === this.finished || !this.current(key)) return;
      this.refine(key);
    }, REST_DELAY_MS);
  }

  /** No more renders for this refinement. One in flight lands and is dropped, not cut
   * off: the server renders it either way, and a request whose client is gone can cost
   * the heavy worker a restart (app/work/pool.py). */
  stop() {
    clearTimeout(this.timer);
    this.run = null;
  }

  /** The data route's URL for one render of the panel's state: its display fields
   * (exposure) are the figure's only. */
  url(samples, seed) {
    const q = this.panel.params(ctx.state);
    for (const f of this.panel.view.fields) if (fieldRole(f) === "display") delete q[f.name];
    return `${API}/${this.panel.name}?${query({ ...q, samples, seed })}`;
  }

  async refine(key) {
    const run = (this.run = { key });
    const params = this.panel.params(ctx.state);
    const first = Number(params.seed ?? 0);
    const exposure = Number(params.exposure ?? 0);
    let average = new RenderAverage(), samples = REST_SAMPLES, seeds = [], busy = 0;
    this.status = { key, renders: 0, samples: 0, noise: null, done: false, seeds };
    for (let j = 1; this.run === run; j++) {
      if (!this.current(key)) return this.stop();
      const seed = (first + j) % MAX_SEED;
      let res, body;
      try {
        res = await fetch(this.url(samples, seed), { headers: { Accept: "application/json" } });
        body = await res.json();
      } catch {
        if (this.run === run) this.run = null;     // the server gone: the next rest tries again
        return;
      }
      if (this.run !== run) return;
      if (!this.current(key)) return this.stop();
      if (res.status === 503 && res.headers.get("Retry-After")) {   // the same render later
        const after = Math.max(Number(res.headers.get("Retry-After")) || 1, 1);
        const wait = Math.max(after, Math.min(after * 2 ** busy++, MAX_BUSY_WAIT_S));
        await new Promise((r) => setTimeout(r, 1000 * wait));
        j -= 1;
        continue;
      }
      busy = 0;
      if (!res.ok) {
        // too much for the budget: renders of half the samples, averaged afresh (equal
        // weights need equal samples); any other refusal ends the refinement here, its
        // last average drawn
        const onSamples = JSON.stringify(body?.detail ?? "").includes("samples");
        if ((res.status === 413 || res.status === 422) && onSamples && samples / 2 >= MIN_SAMPLES) {
          samples /= 2;
          average = new RenderAverage();
          seeds = this.status.seeds = [];
          continue;
        }
        this.run = null;
        return;
      }
      if (!body.std_error) {          // a point light: no sampling, nothing to refine
        this.run = null;
        this.finished = key;
        return;
      }
      average.add(body);
      seeds.push(seed);
      const noise = average.noise();
      Object.assign(this.status, { renders: average.k, samples: average.samples, noise, perRender: samples });
      await this.show(average, exposure, noise, samples, run);
      if (noise <= TARGET_NOISE && this.run === run) {
        this.status.done = true;
        this.finished = key;
        this.run = null;
      }
    }
  }

  /** The average drawn as the panel's figure: its image, and its noise and samples
   * before the heading. */
  async show(average, exposure, noise, perRender, run) {
    const p = this.panel;
    while (p.drawing) await p.drawing.catch(() => {});
    if (this.run !== run) return;
    const canvas = document.createElement("canvas");
    canvas.width = canvas.height = average.n;
    canvas.getContext("2d").putImageData(new ImageData(average.rgba(exposure), average.n, average.n), 0, 0);
    const { data, layout, uirevision, heading } = this.figure;
    const note = samplingNote(noise, average.samples, average.k, perRender);
    const drawable = { data: [{ ...data[0], source: canvas.toDataURL("image/png") }, ...data.slice(1)],
                       layout, uirevision, sub: `${note} · ${heading}`, heading };
    this.own = true;
    const drawing = (p.drawing = Promise.resolve(p.draw(drawable)));
    this.own = false;
    await drawing.catch(() => {}).finally(() => { if (p.drawing === drawing) p.drawing = null; });
  }
}
