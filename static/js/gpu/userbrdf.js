/* Your own BRDF: a Disney BRDF Explorer `.brdf` file opened (picked or dropped) or kept
 * in the link, drawn as a sphere beside the registry model (same light and exposure),
 * its parameters as sliders, and measured from GPU read-backs (measure.js) against the
 * page's current registry model. Every failure — a file too large or not one, a shader
 * that does not compile (with the file's line numbers), an undeclared parameter, a shader
 * that stalls the GPU (context lost) — is a message here; the rest of the page works.
 * Its editor (editor.js; the panel places editor.section) holds the text: what is typed
 * there is opened as a file is. `listen(fn)`: fn() is called whenever what it draws
 * changes — opened, a value or the text changed, closed, lost (usercurves.js, the slice).
 */
import { el, saveBlob } from "../base/dom.js";
import { makeContext, ShaderError } from "./gl.js";
import { SphereRenderer } from "./sphere.js";
import { parseBrdf, defaults, carried, BrdfFileError, MAX_BYTES } from "./brdffile.js";
import { userGlsl, explain } from "./glslprep.js";
import { PairEvaluator, measure, probe, MU, ALBEDO_NODES, FLOOR, FLOAT32_REL, PROBE_LIMIT_MS } from "./measure.js";
import { encodeLink, decodeLink, MAX_LINK_CHARS } from "./link.js";
import { BrdfEditor } from "./editor.js";

/** URL parameter holding the user's BRDF (compressed source and values). */
export const LINK_KEY = "ubrdf";
const MEASURE_DELAY_MS = 500;
const LINK_DELAY_MS = 400;

const fmt = (x, d = 4) => (Number.isFinite(x) ? (Math.abs(x) >= 1e-3 || x === 0 ? x.toFixed(d) : x.toExponential(1)) : String(x));
const sci = (x) => (Number.isFinite(x) ? x.toExponential(1) : String(x));
const place = (w) => (w ? ` at θ_l ${w.theta_l.toFixed(1)}°, φ_l ${w.phi_l.toFixed(1)}°, θ_v ${w.theta_v.toFixed(1)}°, φ_v ${w.phi_v.toFixed(1)}°` : "");

export class UserBrdf {
  /** registry(): {glsl, uniforms, label} of the page's current model, or null;
   * link(text|null): keep the encoded BRDF in the page's URL. */
  constructor({ registry, link }) {
    this.registry = registry;
    this.link = link;
    this.canvas = el("canvas", { class: "gpu-canvas", width: 256, height: 256, id: "gpu-user-canvas", hidden: true,
                                  "aria-label": "Your BRDF's sphere, drawn on the GPU" });
    this.fileInput = el("input", { type: "file", accept: ".brdf,text/plain", id: "gpu-brdf-file" });
    this.messageLine = el("p", { class: "gpu-message", id: "gpu-brdf-message", role: "status", "aria-live": "polite" });
    this.sliders = el("div", { class: "gpu-params", id: "gpu-brdf-params" });
    this.results = el("div", { class: "gpu-measure", id: "gpu-brdf-measure", "aria-live": "polite" });
    this.exportButton = el("button", { type: "button", class: "export", id: "gpu-brdf-export", text: "Export with its numbers", disabled: true });
    this.measureButton = el("button", { type: "button", class: "export", id: "gpu-brdf-measure-now", text: "Measure", disabled: true });
    this.closeButton = el("button", { type: "button", class: "export", id: "gpu-brdf-close", text: "Close", hidden: true,
                                      title: "Take your BRDF off the page (its sphere, sliders, numbers and curves)" });
    this.editor = new BrdfEditor({ apply: (text) => this.open(text, this.values, this.editedName(), { edited: true }) });
    const write = el("button", { type: "button", class: "export", id: "gpu-brdf-write", text: "Write or edit…",
                                 title: "The .brdf's text under the spheres: it redraws as you type" });
    write.addEventListener("click", () => this.editor.reveal());
    this.section = el("div", { class: "gpu-user" },
      el("div", { class: "panel-tools" },
        el("label", {}, "Your BRDF (.brdf, or drop it here) ", this.fileInput), write, this.measureButton, this.exportButton, this.closeButton),
      this.messageLine, this.sliders, this.results);
    this.listeners = [];
    Object.assign(this, { file: null, values: {}, source: null, glsl: null, renderer: null, evaluator: null, measured: null,
                          measureTimer: 0, linkTimer: 0, lost: false, measureCount: 0, opening: 0 });
    this.fileInput.addEventListener("change", () => this.fileInput.files[0] && this.openFile(this.fileInput.files[0]));
    this.measureButton.addEventListener("click", () => this.measureNow());
    this.exportButton.addEventListener("click", () => this.export());
    this.closeButton.addEventListener("click", () => this.close());
  }

  listen(fn) { this.listeners.push(fn); }
  onChange() { for (const fn of this.listeners) fn(); }

  say(text, kind = "") {
    this.messageLine.textContent = text;
    this.messageLine.className = `gpu-message ${kind}`;
  }

  /** The drop target: the whole GPU panel. */
  acceptDrops(zone) {
    zone.addEventListener("dragover", (ev) => { ev.preventDefault(); zone.classList.add("gpu-drop"); });
    zone.addEventListener("dragleave", () => zone.classList.remove("gpu-drop"));
    zone.addEventListener("drop", (ev) => {
      ev.preventDefault();
      zone.classList.remove("gpu-drop");
      const f = ev.dataTransfer?.files?.[0];
      if (f && !this.onOtherFile?.(f)) this.openFile(f);     // another kind (a .hdr) goes to its owner
    });
  }

  async openFile(file) {
    if (file.size > MAX_BYTES) return this.say(`${file.name}: ${(file.size / 1024).toFixed(0)} KB is over the ${MAX_BYTES / 1024} KB a .brdf file may have.`, "error");
    this.open(await file.text(), null, file.name);
  }

  /** The editor's text's name: that of the file it came from, edited. */
  editedName() {
    const base = (this.textName || "").replace(/ \(edited\)$/, "");
    return base && base !== "the BRDF in the link" ? `${base} (edited)` : "your BRDF";
  }

  /** A .brdf text (and values, from a link or kept across edits): parsed, compiled, timed
   * on one pixel (a shader that would stall the GPU is refused before it draws 65 536),
   * drawn, measured. Answers {ok} or {ok: false, message, lines} (the editor's; an edit's
   * failure is said there only, the last good BRDF staying drawn), {stale} when a newer
   * text was opened meanwhile. */
  async open(text, values = null, name = "your BRDF", { edited = false } = {}) {
    const turn = ++this.opening;
    const fail = (message, lines = []) => {
      if (!edited) this.say(`${name}: ${message}`, "error");
      if (!edited && lines.length) {                    // to be fixed in the editor
        this.editor.show(text, message, lines);
        this.textName = name;
      }
      return { ok: false, message, lines };
    };
    let parsed;
    try {
      parsed = parseBrdf(text);
    } catch (e) {
      return e instanceof BrdfFileError ? fail(e.message, e.line ? [e.line] : []) : fail(String(e));
    }
    if (!this.context()) return fail("WebGL2 is not available here");
    const { glsl, offset, limit } = userGlsl(parsed, text.split("\n").length);
    let prog;
    try {
      prog = this.evaluator.compile(glsl, { offset, limit });
    } catch (e) {
      return e instanceof ShaderError ? fail(`the shader does not compile:\n${explain(e.lines)}`, e.lines.map((x) => x.line).filter(Boolean))
        : fail(String(e));
    }
    if (!edited) this.say(`${name}: compiled; timing one pixel…`);
    const gl = this.renderer.gl;
    const kept = carried(parsed.params, values, edited ? this.file?.params ?? [] : null);
    const ms = await probe(gl, prog, { ...defaults(parsed.params), ...kept });
    if (turn !== this.opening) { gl.deleteProgram(prog); return { stale: true }; }
    if (ms === null) {
      this.say(`${name}: one pixel of its shader was still running after ${PROBE_LIMIT_MS} ms (an endless or very long loop?): `
        + "refused before it could stall the GPU; the GPU context is reset. Fix the shader and open it again.", "error");
      this.stalled = true;
      gl.getExtension("WEBGL_lose_context")?.loseContext();
      return { ok: false, message: this.messageLine.textContent, lines: [] };
    }
    this.renderer.setSource(glsl, { offset, limit });
    if (this.prog) this.renderer.gl.deleteProgram(this.prog);
    Object.assign(this, { file: parsed, source: text, name, prog, glsl: { glsl, offset, limit },
                          values: { ...defaults(parsed.params), ...kept } });
    if (!edited) {
      this.editor.show(text);
      this.textName = name;
    }
    this.buildSliders();
    this.canvas.hidden = false;
    this.measureButton.disabled = this.exportButton.disabled = false;
    this.closeButton.hidden = false;
    this.say(`${name}: ${parsed.params.length} parameter${parsed.params.length === 1 ? "" : "s"}; drawn beside the registry model (same light and exposure).`);
    this.draw();
    this.scheduleMeasure();
    this.scheduleLink();
    this.onChange();
    return { ok: true };
  }

  /** The BRDF's own WebGL2 context (its stalls and losses are its own). */
  context() {
    if (this.renderer && !this.lost) return true;
    this.renderer = this.evaluator = null;
    if (this.lost) {                   // a lost context stays lost: a new canvas, a new context
      const fresh = el("canvas", { class: "gpu-canvas", width: 256, height: 256, id: "gpu-user-canvas", hidden: true,
                                   "aria-label": "Your BRDF's sphere, drawn on the GPU" });
      this.canvas.replaceWith(fresh);
      this.canvas = fresh;
      this.lost = false;
      this.otherSource = this.otherProg = null;
    }
    const { gl, why } = makeContext(this.canvas);
    if (!gl) { this.say(`Your BRDF cannot be drawn here: ${why}.`, "error"); return false; }
    this.canvas.addEventListener("webglcontextlost", (ev) => {
      ev.preventDefault();
      this.lost = true;
      this.renderer = this.evaluator = this.prog = null;
      this.canvas.hidden = true;
      if (!this.stalled) {
        this.say(`The GPU stopped ${this.name || "your BRDF"}'s shader and lost its context (the shader ran too long — `
          + "an endless or very long loop?). The BRDF is unloaded; the rest of the page works. Fix the shader and open it again.", "error");
      }
      this.stalled = false;
      this.file = null;
      this.closeButton.hidden = true;
      this.link(null);
      this.onChange();
    });
    this.renderer = new SphereRenderer(gl, 256);
    this.evaluator = new PairEvaluator(gl);
    return true;
  }

  buildSliders() {
    this.sliders.textContent = "";
    for (const p of this.file.params) {
      const id = `gpu-p-${p.name}`;
      let input, out = null;
      if (p.type === "float") {
        input = el("input", { type: "range", id, min: String(p.lo), max: String(p.hi), step: String((p.hi - p.lo) / 1000), value: String(this.values[p.name]) });
        out = el("output", { for: id, text: fmt(this.values[p.name], 3) });
        input.addEventListener("input", () => { this.values[p.name] = Number(input.value); out.value = fmt(this.values[p.name], 3); this.changed(); });
      } else if (p.type === "bool") {
        input = el("input", { type: "checkbox", id });
        input.checked = !!this.values[p.name];
        input.addEventListener("change", () => { this.values[p.name] = input.checked; this.changed(); });
      } else {
        const hex = (c) => "#" + c.map((x) => Math.round(x * 255).toString(16).padStart(2, "0")).join("");
        input = el("input", { type: "color", id, value: hex(this.values[p.name]) });
        input.addEventListener("input", () => {
          this.values[p.name] = [1, 3, 5].map((k) => parseInt(input.value.slice(k, k + 2), 16) / 255);
          this.changed();
        });
      }
      this.sliders.append(el("label", { class: "gpu-param" }, `${p.name} `, input, out ? " " : "", out || ""));
    }
  }

  changed() {
    this.draw();
    this.scheduleMeasure();
    this.scheduleLink();
    this.onChange();
  }

  /** Taken off the page: its sphere, sliders, numbers, link and curves; the editor keeps
   * the text (typing there opens it again). */
  close() {
    if (!this.file) return;
    clearTimeout(this.measureTimer);
    clearTimeout(this.linkTimer);
    this.opening++;                                    // an open still under way is stale
    Object.assign(this, { file: null, measured: null });
    this.canvas.hidden = this.closeButton.hidden = true;
    this.measureButton.disabled = this.exportButton.disabled = true;
    this.sliders.textContent = this.results.textContent = "";
    this.link(null);
    this.say(`${this.name} closed.`);
    this.onChange();
  }

  /** f (RGBA float32 per pair) at direction pairs (flat arrays of 3·count, n = +z), or
   * null when no BRDF is open. */
  evaluate(l, v) {
    if (!this.file || !this.prog || this.lost) return null;
    return this.evaluator.run(this.prog, this.values, l, v);
  }

  /** The registry sphere's light and exposure, kept for a renderer made later. */
  setLight(l) { this.light = l; }
  setExposure(e) { this.exposure = e; }

  draw() {
    if (!this.file || !this.renderer || this.lost) return;
    this.renderer.setLight(this.light || [0, 0, 1]);
    this.renderer.exposure = this.exposure ?? 0;
    this.renderer.uniforms = this.values;
    this.renderer.draw();
  }

  scheduleMeasure() {
    clearTimeout(this.measureTimer);
    this.measureTimer = setTimeout(() => this.measureNow(), MEASURE_DELAY_MS);
  }

  /** Measures now; the registry model compiled into this context for the comparison. */
  measureNow() {
    clearTimeout(this.measureTimer);
    if (!this.file || !this.prog || this.lost) return null;
    const reg = this.registry();
    let other = null;
    if (reg) {
      try {
        if (reg.glsl !== this.otherSource) {
          if (this.otherProg) this.renderer.gl.deleteProgram(this.otherProg);
          this.otherProg = this.evaluator.compile(reg.glsl);
          this.otherSource = reg.glsl;
        }
        other = { prog: this.otherProg, uniforms: reg.uniforms };
      } catch { other = null; }
    }
    const m = measure(this.evaluator, this.prog, this.values, other);
    if (this.lost) return null;
    this.measured = { ...m, against: reg ? reg.label : null, values: { ...this.values } };
    this.measureCount++;
    this.showMeasure();
    return this.measured;
  }

  showMeasure() {
    const m = this.measured;
    const rows = [];
    const E = m.albedo.map((a) => `μ ${a.mu}: ${a.E.map((x) => fmt(x)).join(" / ")} ± ${sci(a.error)}`).join("; ");
    rows.push(`Albedo E(μ_v) (R / G / B; Gauss-Legendre ${ALBEDO_NODES.mu} μ × ${ALBEDO_NODES.phi} φ, ± its difference from half the nodes + ${FLOAT32_REL} relative for float32): ${E}.`);
    const f = m.furnace;
    const over = f.E > 1 + f.error;
    rows.push(`White furnace: largest E = ${fmt(f.E)} ± ${sci(f.error)} at μ = ${f.mu} — ${over ? "it creates energy (E > 1)" : "no energy created (E ≤ 1)"}.`);
    rows.push(`Reciprocity f(l, v) = f(v, l): largest relative difference ${sci(m.reciprocity.max)}${m.reciprocity.max > 1e-5 ? place(m.reciprocity.at) : ""} over 4096 pairs (θ ≤ 88°).`);
    const p = m.positivity;
    rows.push(p.negative ? `Positivity: ${p.negative} negative values, the lowest ${sci(p.min)}${place(p.minAt)}.` : "Positivity: no negative value.");
    rows.push(p.nonFinite ? `NaN/∞: ${p.nonFinite} values, the first (${p.firstNonFinite.value})${place(p.firstNonFinite)}.` : `NaN/∞: none in ${m.pairs} evaluations.`);
    if (m.difference) {
      const d = m.difference;
      rows.push(`Against the registry model (${m.against}): largest relative difference ${sci(d.max)}${place(d.at)} over ${d.pairs} pairs `
        + `(θ ≤ 88°; below ${FLOOR}× its peak a difference counts against that floor); its E(μ) ${d.albedo.map((a) => fmt(a.E[0])).join(", ")} at μ ${MU.join(", ")}.`);
    } else rows.push("Against the registry model: its code is not available here (see the live sphere's message).");
    this.results.textContent = "";
    for (const r of rows) this.results.append(el("p", { text: r }));
  }

  scheduleLink() {
    clearTimeout(this.linkTimer);
    this.linkTimer = setTimeout(async () => {
      if (!this.file) return;
      const text = await encodeLink(this.source, this.values);
      if (text.length > MAX_LINK_CHARS) {
        this.link(null);
        this.say(`${this.name}: too long to keep in the link (${text.length} characters compressed, at most ${MAX_LINK_CHARS}); use Export.`);
      } else this.link(text);
    }, LINK_DELAY_MS);
  }

  /** A BRDF from the page's link, if it holds one. */
  async fromLink(text) {
    try {
      const { source, values } = await decodeLink(text);
      this.open(source, values, "the BRDF in the link");
    } catch (e) {
      this.say(`The BRDF in the link cannot be read: ${e.message}`, "error");
    }
  }

  export() {
    if (!this.file) return;
    const m = this.measured || this.measureNow();
    const body = { format: "BRDF Lobe Explorer: a user BRDF and its measurements", name: this.name, values: this.values,
                   parameters: this.file.params, measured: m, source: this.source };
    saveBlob(new Blob([JSON.stringify(body, null, 1)], { type: "application/json" }), `${(this.name || "brdf").replace(/\.brdf$/, "")}.measured.json`);
  }

  hook() {
    const self = this;
    return {
      open: (text) => self.open(text, null, "test.brdf"),
      measure: () => self.measureNow(),
      get message() { return self.messageLine.textContent; },
      get loaded() { return !!self.file; },
      get values() { return { ...self.values }; },
      get measured() { return self.measured; },
      get measureCount() { return self.measureCount; },
      get source() { return self.source; },
      get settled() { return self.editor.settled; },
      setValue(name, v) { self.values[name] = v; self.changed(); },
      /** f at direction pairs (flat arrays of 3·count, n = +z): RGBA per pair. */
      evaluate: (l, v) => Array.from(self.evaluate(l, v)),
      close: () => self.close(),
      /** The sphere's radiance frame counted: pixels on the disk, lit (> 0), NaN/∞, and
       * the sum of its finite radiance. */
      sphere() {
        self.renderer.render();
        const px = self.renderer.read();
        const out = { disk: 0, lit: 0, nonFinite: 0, total: 0 };
        for (let i = 0; i < px.length; i += 4) {
          if (px[i + 3] === 0) continue;
          const c = [px[i], px[i + 1], px[i + 2]];
          out.disk++;
          if (!c.every(Number.isFinite)) { out.nonFinite++; continue; }
          if (c.some((x) => x > 0)) out.lit++;
          out.total += c[0] + c[1] + c[2];
        }
        return out;
      },
    };
  }
}
