/* The GPU panel's 3-D lobe view: the registry model's lobe (lobe3d.js) and, beside it,
 * the user's BRDF's, for the panel's light, on one scale (the larger of the two peaks) and
 * turned together by dragging on either (azimuth and elevation; no server round trip).
 * Each lobe has its own WebGL2 context: a user's shader that is lost takes only its own.
 * Its truth line (lobe3dtruth.js) is shown with the panel's truth toggle.
 */
import { el } from "../base/dom.js";
import { makeContext } from "./gl.js";
import { LobeRenderer, orbit, FILL } from "./lobe3d.js";
import { LobeTruth } from "./lobe3dtruth.js";

/** Degrees turned per pixel dragged. */
const TURN_PER_PX = 0.5;
/** The elevation stays within these (degrees): from just below the horizon to the top. */
const ELEVATION = [-10, 90];

export class Lobe3dView {
  constructor(size) {
    const canvas = (id, label) => el("canvas", { class: "gpu-canvas gpu-lobe3d", width: size, height: size, id, hidden: true,
                                                  title: "Drag to turn the lobe", "aria-label": label });
    this.canvas = canvas("gpu-lobe3d-canvas", "The model's lobe f·cos θ_o over the hemisphere, drawn on the GPU");
    this.userCanvas = canvas("gpu-user-lobe3d-canvas", "Your BRDF's lobe f·cos θ_o, on the same scale, drawn on the GPU");
    this.input = el("input", { type: "checkbox", id: "gpu-lobe3d-toggle" });
    Object.assign(this, { on: false, azimuth: -30, elevation: 25, reg: null, user: null, registry: null, brdf: null,
                          light: [0, 0, 1], zoom: 1, key: null, why: null, draws: 0, truthOn: false });
    this.truthLine = new LobeTruth();
    this.truthText = this.truthLine.text;
    for (const c of [this.canvas, this.userCanvas]) this.orbitHandlers(c);
  }

  orbitHandlers(c) {
    let last = null;
    c.addEventListener("pointerdown", (ev) => {
      if (ev.button !== 0) return;
      ev.preventDefault();
      c.setPointerCapture?.(ev.pointerId);
      last = [ev.clientX, ev.clientY];
    });
    c.addEventListener("pointermove", (ev) => {
      if (!last) return;
      this.turn(ev.clientX - last[0], ev.clientY - last[1]);
      last = [ev.clientX, ev.clientY];
    });
    for (const end of ["pointerup", "pointercancel"]) c.addEventListener(end, () => { last = null; });
  }

  /** Turned by a drag of (dx, dy) pixels: redrawn at once, the scale kept. */
  turn(dx, dy) {
    this.azimuth += dx * TURN_PER_PX;
    this.elevation = Math.min(ELEVATION[1], Math.max(ELEVATION[0], this.elevation + dy * TURN_PER_PX));
    this.paint();
  }

  setOn(on) {
    this.on = on;
    this.input.checked = on;
    this.key = null;
    this.showTruth(this.truthOn);
    return this.update(this.registry, this.brdf, this.light);
  }

  /** registry: {glsl, uniforms} of the page's model (null: none yet); brdf: the UserBrdf;
   * light: unit ω_i. Drawn when shown and something changed; answers why not, or null. */
  update(registry, brdf, light) {
    Object.assign(this, { registry, brdf, light });
    const mine = brdf?.file && brdf.glsl ? brdf : null;
    this.canvas.hidden = !this.on;
    this.userCanvas.hidden = !(this.on && mine);
    this.truthLine.setUser(!this.userCanvas.hidden);
    if (!this.on || !registry) return null;
    const key = JSON.stringify([registry.glsl, registry.uniforms, light, mine && [mine.glsl.glsl, mine.values]]);
    if (key === this.key) return null;
    this.why = null;
    const peaks = [this.load("reg", this.canvas, registry.glsl, registry.uniforms)];
    if (mine) peaks.push(this.load("user", this.userCanvas, mine.glsl.glsl, mine.values));
    const top = Math.max(...peaks.filter(Number.isFinite));
    this.zoom = top > 0 ? FILL / top : 1;
    this.key = key;
    this.paint();
    return this.why;
  }

  /** A lobe's renderer (made on first use), its source, values and light: its peak. */
  load(which, canvas, glsl, uniforms) {
    if (!this[which]) {
      const { gl, why } = makeContext(canvas);
      if (!gl) { this.why = `No GPU 3-D lobe: ${why}.`; return NaN; }
      this[which] = new LobeRenderer(gl);
    }
    const r = this[which];
    if (r.gl.isContextLost()) { this.why = "The 3-D lobe's GPU context was lost."; return NaN; }
    try {
      r.setSource(glsl);
    } catch (e) {
      this.why = `The 3-D lobe cannot compile ${which === "reg" ? "this model" : "your BRDF"}: ${e.message}`;
      r.prog = null;
      return NaN;
    }
    Object.assign(r, { uniforms, light: this.light });
    return r.peak();
  }

  paint() {
    const view = orbit(this.azimuth, this.elevation);
    for (const [r, c] of [[this.reg, this.canvas], [this.user, this.userCanvas]]) {
      if (!r || c.hidden || r.gl.isContextLost()) continue;
      r.view = view;
      r.draw(this.zoom);
    }
    this.draws++;
  }

  /** truthOn: the panel's toggle; the line is shown while the lobe is. */
  showTruth(truthOn) {
    this.truthOn = truthOn;
    this.truthLine.show(this.on && truthOn);
  }

  truthStale() { if (this.on && this.truthOn) this.truthLine.stale(); }

  /** The registry lobe as drawn against the server's float64 f of `model` (its query);
   * current(): this answer is still wanted. */
  checkTruth(model, current) {
    if (!this.on) return null;
    return this.truthLine.check(this.reg, model, current);
  }

  get truth() { return this.truthLine.truth; }

  /** r = f·cos θ_o at directions (θ_o, φ_o) in degrees, read back: {registry, user}. */
  radii(anglesDeg) {
    const d = anglesDeg.flatMap(([t, p]) => [Math.sin(t * Math.PI / 180) * Math.cos(p * Math.PI / 180),
      Math.sin(t * Math.PI / 180) * Math.sin(p * Math.PI / 180), Math.cos(t * Math.PI / 180)]);
    const of = (r, c) => (r && !c.hidden && r.prog ? Array.from(r.radii(d)) : null);
    return { registry: of(this.reg, this.canvas), user: of(this.user, this.userCanvas) };
  }
}
