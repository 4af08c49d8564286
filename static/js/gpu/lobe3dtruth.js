/* The 3-D lobe's truth line: the radius r = f·cos θ_o that the vertex shader computes
 * (lobe3d.js), read back at the mesh's distinct directions, against the server's float64
 * f (POST /api/v1/eval) at the same float32 directions and float32 light, times cos θ_o
 * of the direction sent. Stated as truth.js states the sphere's: the largest and mean
 * relative difference where θ_i, θ_o ≤ GRAZING_DEG, the largest over all directions in
 * units of the peak, FLOOR·peak the least denominator. The user's BRDF's lobe has no
 * float64 reference (the server cannot run the user's GLSL): the line says so.
 */
import { el } from "../base/dom.js";
import { MESH } from "./lobe3d.js";
import { referenceF, compareSamples, anglesDeg, fmt, FLOOR, GRAZING_DEG, MU_MIN } from "./truth.js";

/** Indices into the mesh of its distinct directions: the pole once (row θ_o = 0 is
 * MESH.phi copies of it) and each other row without its φ_o = 360° end (φ_o = 0° again):
 * 1 + 64·128 = 8193. */
export function distinctMesh() {
  const out = [0];
  for (let i = 1; i < MESH.theta; i++) for (let j = 0; j + 1 < MESH.phi; j++) out.push(i * MESH.phi + j);
  return out;
}

const NO_USER_REFERENCE = " Your BRDF's lobe beside it has no float64 reference: the server cannot run your GLSL.";

export class LobeTruth {
  constructor() {
    this.text = el("p", { class: "gpu-truth", id: "gpu-lobe3d-truth", role: "status", hidden: true });
    Object.assign(this, { truth: null, line: "", withUser: false, picks: distinctMesh() });
  }

  show(visible) { this.text.hidden = !visible; }

  /** withUser: the user's lobe is shown beside the model's (the line says it has no reference). */
  setUser(withUser) {
    this.withUser = withUser;
    this.say(this.line);
  }

  say(line) {
    this.line = line;
    const text = line + (this.withUser ? NO_USER_REFERENCE : "");
    if (this.text.textContent !== text) this.text.textContent = text;
  }

  /** The light or the model changed: the numbers no longer describe the lobe drawn. */
  stale() {
    this.truth = null;
    this.say("3-D lobe: comparing with the server's float64 f (/eval)…");
  }

  /** renderer: the registry lobe's LobeRenderer (its model and light loaded); model: its
   * query; current(): this answer is still wanted. */
  async check(renderer, model, current) {
    if (!renderer?.prog || renderer.gl.isContextLost()) {
      this.truth = null;
      this.say("3-D lobe: not drawn, nothing to compare.");
      return;
    }
    const dirs = new Float32Array(3 * this.picks.length);
    this.picks.forEach((m, k) => dirs.set(renderer.meshDirs.subarray(3 * m, 3 * m + 3), 3 * k));
    const light = Float32Array.from(renderer.light);       // the uniform the shader read
    const gpu = renderer.radii(dirs);
    let f;
    try {
      f = await referenceF(model, light, dirs);
    } catch (e) {
      if (current()) this.say(`3-D lobe: no reference: ${e.message}`);
      return;
    }
    if (!current()) return;
    const count = this.picks.length, ref = new Float64Array(count);
    for (let k = 0; k < count; k++) {
      const [x, y, z] = dirs.subarray(3 * k, 3 * k + 3);
      ref[k] = f[k] * (z / Math.hypot(x, y, z));           // cos θ_o of the direction sent
    }
    const lightIn = light[2] >= MU_MIN;
    const r = compareSamples(gpu, ref, count, { gpuStride: 1, refStride: 1, channels: 1,
                                                inBand: (k) => lightIn && dirs[3 * k + 2] >= MU_MIN });
    const at = r.at === null ? null : anglesDeg(...dirs.subarray(3 * r.at, 3 * r.at + 3));
    this.truth = { max: r.max, mean: r.mean, at, directions: r.pixels, all: r.disk, absPeak: r.absPeak,
                   nonFinite: r.nonFinite, peak: r.peak, dirs: Array.from(dirs), light: Array.from(light) };
    const where = at ? ` at θ_o = ${at[0].toFixed(1)}°, φ_o = ${at[1].toFixed(1)}°` : "";
    const band = lightIn
      ? `largest relative difference ${fmt(r.max)}${where}, mean ${fmt(r.mean)} over the ${r.pixels} mesh directions `
        + `with θ_o ≤ ${GRAZING_DEG}°`
      : `the light is beyond θ_i = ${GRAZING_DEG}°: no relative difference stated`;
    this.say(`3-D lobe (f·cos θ_o), GPU against the server's float64 f (/eval) at the same float32 `
      + `directions: ${band}; largest difference over all ${r.disk} directions ${fmt(r.absPeak)} of the peak`
      + (r.nonFinite ? `; ${r.nonFinite} directions NaN/∞` : "")
      + `; below ${FLOOR}× the peak a difference counts against that floor.`);
  }
}
