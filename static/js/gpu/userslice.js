/* Your BRDF's θ_h–θ_d slice beside the registry model's: slice.js's renderer (the same
 * float64-formed directions, Burley 2012 fig. 3's image slice) drawn from the .brdf's
 * GLSL as the registry's is drawn from the generated GLSL, on the registry slice's colour
 * scale so the two compare by eye (where yours is brighter it clips). Its own WebGL2
 * context: a user's shader that stalls or is lost takes only this canvas with it.
 */
import { el } from "../base/dom.js";
import { makeContext } from "./gl.js";
import { SliceRenderer } from "./slice.js";

export class UserSlice {
  constructor(size) {
    this.size = size;
    this.canvas = el("canvas", { class: "gpu-canvas", width: size, height: size, id: "gpu-user-slice-canvas", hidden: true,
                                 "aria-label": "Your BRDF's f over θ_h (right) and θ_d (up), on the registry slice's scale, drawn on the GPU" });
    Object.assign(this, { slice: null, key: null, why: null });
  }

  /** Drawn for `user` (a UserBrdf) at the azimuths (degrees) on `logRange` when `on` and a
   * BRDF is open; hidden otherwise. Answers why not when it cannot be drawn, else null. */
  draw(user, on, phiH, phiD, logRange) {
    const shown = on && !!user.file && !!user.glsl;
    this.canvas.hidden = !shown;
    if (!shown) { this.key = null; return null; }
    if (!this.slice) {
      const { gl, why } = makeContext(this.canvas);
      if (!gl) return (this.why = `No GPU slice of your BRDF: ${why}.`);
      this.slice = new SliceRenderer(gl, this.size);
    }
    if (this.slice.gl.isContextLost()) return (this.why = "The GPU context of your BRDF's slice was lost.");
    const key = JSON.stringify([user.glsl.glsl, user.values, phiH, phiD, logRange]);
    if (key === this.key) return null;
    try {
      this.slice.setSource(user.glsl.glsl, user.glsl);
    } catch (e) {
      return (this.why = `Your BRDF's slice cannot compile: ${e.message}`);
    }
    this.slice.setAzimuths(phiH, phiD);
    this.slice.uniforms = user.values;
    this.slice.draw(logRange);
    this.key = key;
    return (this.why = null);
  }

  /** f (float32 RGBA per pixel, rows θ_d from 0) and the directions drawn, for tests. */
  read() {
    if (!this.slice || this.canvas.hidden) return null;
    this.slice.render();
    return { f: this.slice.read(), ...this.slice.dirs };
  }
}
