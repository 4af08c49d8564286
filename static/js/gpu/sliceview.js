/* The GPU panel's θ_h–θ_d slice view: the registry model's slice (slice.js, its own
 * context) and the user's BRDF's beside it on its scale (userslice.js), its toggle, and
 * its truth against the server's float64 slice at the same float32 directions (truth.js).
 */
import { el } from "../base/dom.js";
import { makeContext } from "./gl.js";
import { SliceRenderer } from "./slice.js";
import { UserSlice } from "./userslice.js";
import { referenceSlice, compareSlice, fmt, GRAZING_DEG } from "./truth.js";

/** The GPU slice's azimuths: φ_h = 0, φ_d = 90° (the Disney explorer's default image slice). */
export const SLICE_PHI_H = 0, SLICE_PHI_D = 90;

export class SliceView {
  /** say(text, kind): the panel's message line. */
  constructor(size, { say }) {
    Object.assign(this, { size, say, on: false, slice: null, key: null, truth: null });
    this.input = el("input", { type: "checkbox", id: "gpu-slice-toggle" });
    this.canvas = el("canvas", { class: "gpu-canvas", width: size, height: size, id: "gpu-slice-canvas", hidden: true,
                                 "aria-label": "f over θ_h (right) and θ_d (up) at φ_d = 90°, log scale, drawn on the GPU" });
    this.truthText = el("p", { class: "gpu-truth", id: "gpu-slice-truth", role: "status", hidden: true });
    this.user = new UserSlice(size);
  }

  /** Shown or not (its own context made the first time); truthOn: the panel's toggle. */
  setOn(on, truthOn) {
    this.on = on;
    this.canvas.hidden = !on;
    this.showTruth(truthOn);
    if (on && !this.slice) {
      const { gl, why } = makeContext(this.canvas);
      if (!gl) { this.say(`No GPU slice: ${why}.`, "error"); return; }
      this.slice = new SliceRenderer(gl, this.size);
      this.slice.setAzimuths(SLICE_PHI_H, SLICE_PHI_D);
    }
    this.key = null;
  }

  showTruth(truthOn) { this.truthText.hidden = !(this.on && truthOn); }

  /** code: /code's answer for the model (glsl: its structure); brdf: the UserBrdf. Drawn
   * when the model or its values changed (the light does not enter the slice); then the
   * user's BRDF's slice on its scale. */
  draw(code, glsl, brdf) {
    if (this.on && this.slice && code && !this.slice.gl.isContextLost()) {
      const key = `${code.code}\n${JSON.stringify(code.uniforms)}`;
      if (key !== this.key) {
        try {
          this.slice.setSource(glsl);
        } catch (err) {
          this.say(`The slice cannot compile this model: ${err.message}`, "error");
          return;
        }
        this.slice.uniforms = code.uniforms;
        this.slice.draw();
        this.key = key;
      }
    }
    this.drawUser(brdf);
  }

  drawUser(brdf) {
    const why = this.user.draw(brdf, this.on, SLICE_PHI_H, SLICE_PHI_D, this.slice?.logRange ?? null);
    if (why) this.say(why, "error");
  }

  /** The registry slice against the server's float64 reference of `model`: stated, and
   * kept in `truth`; current(): this answer is still wanted (no change meanwhile). */
  async checkTruth(model, current) {
    if (!this.on || !this.slice) { this.truth = null; return; }
    this.slice.render();
    const gpu = this.slice.read(), { l, v } = this.slice.dirs, n = this.size;
    let ref;
    try {
      ref = await referenceSlice(model, SLICE_PHI_H, SLICE_PHI_D, n);
    } catch (e) {
      if (current()) this.truthText.textContent = `No reference slice: ${e.message}`;
      return;
    }
    if (!current()) return;
    const r = compareSlice(gpu, ref, n, l, v);
    this.truth = { max: r.max, mean: r.mean, at: r.at, pixels: r.pixels, absPeak: r.absPeak, nonFinite: r.nonFinite };
    this.truthText.textContent = `Slice (φ_d = ${SLICE_PHI_D}°), GPU against the server's float64 at the same float32 `
      + `directions: largest relative difference ${fmt(r.max)}, mean ${fmt(r.mean)} over the ${r.pixels} pixels with `
      + `θ_l, θ_v ≤ ${GRAZING_DEG}°; largest difference over all ${r.disk} pixels ${fmt(r.absPeak)} of the peak`
      + (r.nonFinite ? `; ${r.nonFinite} pixels NaN/∞` : "") + ".";
  }
}
