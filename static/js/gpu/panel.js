/* The "Live sphere (GPU)" panel: the page's model drawn per pixel in WebGL2 from
 * GET /api/v1/code?form=uniform (a slider changes uniforms; a new model compiles once),
 * the light dragged with the pointer (no server round trip), an exposure, and the truth
 * toggle (truth.js). Where WebGL2 or float targets are missing, or the server has no
 * shader for the model, the panel says so and the server's sphere panel is the view.
 * Its other views are modules of their own: the environment sphere (env.js), the
 * θ_h–θ_d slice (sliceview.js) and the 3-D lobe (lobe3dview.js); the user's BRDF
 * (userbrdf.js) is drawn in each of them beside the model.
 */
import { API, el, apiMessage, query } from "../base/dom.js";
import { modelQuery } from "../state/model.js";
import { fam } from "../state/families.js";
import { makeContext, ShaderError } from "./gl.js";
import { SphereRenderer } from "./sphere.js";
import { referenceFrame, compare, diffImage, sphereTruthText } from "./truth.js";
import { SliceView } from "./sliceview.js";
import { Lobe3dView } from "./lobe3dview.js";
import { lightAt } from "../panels/spheredrag.js";
import { UserBrdf, LINK_KEY } from "./userbrdf.js";
import { EnvSphere, ENVIRONMENTS, MAP, PREVIEW_SIZE } from "./env.js";

/** Pixels across the live sphere (bench/gpu_sphere.py's 256²). */
export const SIZE = 256;
const DEG = Math.PI / 180;
/** After the last change, wait this long before asking the server for the truth frame
 * (a drag or a slider would otherwise ask at every step). */
const TRUTH_DELAY_MS = 250;
/** Sample pairs per pixel at which the environment sphere stops accumulating. */
const ENV_MAX_SAMPLES = 4096;
/** The environment sphere's noise goal at rest (issue 34: "honestly stated noise ≤ 5 %"). */
const ENV_NOISE_GOAL = 0.05;
/** The environment sphere accumulates coarse (env.js's preview) while its input changes:
 * during a drag, and until this long after the last of a burst of changes (a slider). */
const SETTLE_MS = 250;
/** Every this many frames at rest the environment sphere's noise is read back and stated. */
const ENV_REPORT_FRAMES = 4;
/** The user's .hdr is drawn from at most this many cells across (POST
 * /api/v1/environments/hdr?format=f32 averages it over solid angle): 256 × 128 cells of
 * ~1.4°, finer than the 1.8° a pixel of the 256² sphere spans near its centre. */
const MAP_WIDTH = 256;
/** Input-to-frame times kept for the benchmark hook. */
const TIMINGS_KEPT = 2000;

/** (θ, φ) in degrees → unit vector (sin θ cos φ, sin θ sin φ, cos θ), the server's
 * direction_deg. */
export const direction = (thetaDeg, phiDeg) => [Math.sin(thetaDeg * DEG) * Math.cos(phiDeg * DEG),
  Math.sin(thetaDeg * DEG) * Math.sin(phiDeg * DEG), Math.cos(thetaDeg * DEG)];

/** The generated code with its comments gone: two models whose code differs only in
 * the comments (the parameter values quoted there) run one compiled program. */
const structure = (code) => code.replace(/\/\/[^\n]*/g, "").replace(/[ \t]+\n/g, "\n");

export class GpuPanel {
  /** onLight(θ, φ): the drag's light, written to the page's state at the release;
   * onFallback(why): WebGL2 is unusable here (the page shows the server's sphere). */
  constructor({ onLight, onFallback, onLink }) {
    this.onLight = onLight;
    this.onFallback = onFallback;
    this.user = new UserBrdf({
      registry: () => (this.code && this.model ? { glsl: this.code.code, uniforms: this.code.uniforms, label: query(this.model) } : null),
      link: (text) => onLink?.(LINK_KEY, text),
    });
    this.canvas = el("canvas", { class: "gpu-canvas", width: SIZE, height: SIZE, id: "gpu-canvas",
                                  title: "Drag on the sphere to move the light", "aria-label": "The lit sphere, drawn on the GPU" });
    this.diffCanvas = el("canvas", { class: "gpu-canvas gpu-diff", width: SIZE, height: SIZE, id: "gpu-diff", hidden: true,
                                      "aria-label": "Relative difference from the server's float64 frame" });
    this.message = el("p", { class: "gpu-message", id: "gpu-message", role: "status", "aria-live": "polite" });
    this.truthText = el("p", { class: "gpu-truth", id: "gpu-truth", role: "status", "aria-live": "polite", hidden: true });
    this.exposureInput = el("input", { type: "range", min: "-6", max: "10", step: "0.5", value: "3", id: "gpu-exposure",
                                       "aria-label": "Exposure (stops)" });
    this.exposureText = el("output", { for: "gpu-exposure", text: "+3" });
    this.truthButton = el("button", { type: "button", class: "export", id: "gpu-truth-toggle", "aria-pressed": "false",
                                      text: "Truth: off", title: "Compare each pixel with the server's float64 render of the same frame" });
    this.envSelect = el("select", { id: "gpu-env", "aria-label": "Environment of the second sphere" },
      el("option", { value: "", text: "no environment" }), ...ENVIRONMENTS.map((e) => el("option", { value: e, text: e })));
    this.mapOption = el("option", { value: MAP, text: "your .hdr", hidden: true, disabled: true });
    this.envSelect.append(this.mapOption);
    this.mapInput = el("input", { type: "file", accept: ".hdr,image/vnd.radiance", id: "gpu-hdr",
                                  "aria-label": "Open a Radiance .hdr environment (equirectangular)" });
    this.sliceView = new SliceView(SIZE, { say: (text, kind) => this.say(text, kind) });
    this.user.listen(() => this.sliceView.drawUser(this.user));
    this.lobe3d = new Lobe3dView(SIZE);
    this.legendLine = el("p", { class: "gpu-legend", id: "gpu-legend", hidden: true });
    this.user.listen(() => { this.lobe3dDraw(); this.legend(); });
    this.envCanvas = el("canvas", { class: "gpu-canvas", width: SIZE, height: SIZE, id: "gpu-env-canvas", hidden: true,
                                    "aria-label": "The sphere under the environment, drawn on the GPU" });
    this.envText = el("p", { class: "gpu-message", id: "gpu-env-text", role: "status", hidden: true });
    const tools = el("div", { class: "panel-tools gpu-tools" },
      el("label", {}, "exposure ", this.exposureInput, " ", this.exposureText),
      el("label", {}, "environment ", this.envSelect), el("label", {}, ".hdr ", this.mapInput),
      el("label", {}, this.sliceView.input, " θ_h–θ_d slice"), el("label", {}, this.lobe3d.input, " 3-D lobe"), this.truthButton);
    this.section = el("section", { class: "panel gpu-panel", id: "panel-gpu", "aria-labelledby": "h-gpu" },
      el("div", { class: "panel-head" }, el("h2", { id: "h-gpu", text: "Live sphere (GPU)" }), tools),
      el("div", { class: "gpu-main" },          // the spheres, and under them the .brdf being edited
        this.legendLine,
        el("div", { class: "gpu-views" }, this.canvas, this.user.canvas, this.envCanvas, this.sliceView.canvas,
                        this.sliceView.user.canvas, this.lobe3d.canvas, this.lobe3d.userCanvas, this.diffCanvas),
        this.user.editor.section),
      this.message, this.truthText, this.sliceView.truthText, this.lobe3d.truthText, this.envText, this.user.section,
      el("p", { class: "gpu-caption", text: "The current model drawn per pixel in your browser's WebGL2 from the generated shader "
        + "(L_o/E = f·cos θ_l, 256²); drag on it to move the light. Truth compares it with the server's float64 frame. "
      + "Open a Disney BRDF Explorer .brdf file, or write one under the spheres, to see yours beside it, measured." }));
    this.user.acceptDrops(this.section);
    this.user.onOtherFile = (f) => /\.hdr$/i.test(f.name) && (this.openHdr(f), true);
    Object.assign(this, { renderer: null, ok: false, modelKey: null, codeRequest: null, model: null, dragging: false,
                          frameQueued: false, inputTime: null, timings: [], compiles: 0, draws: 0, truthOn: false,
                          truthTimer: 0, truthToken: 0, codeInflight: false, codeWanted: null, truth: null, state: null,
                          envPreview: true, envChanged: -Infinity, envInput: null, envTimings: [], envFrames: [], envHistory: [] });
    this.exposureInput.addEventListener("input", () => {
      this.renderer && (this.renderer.exposure = Number(this.exposureInput.value));
      this.user.setExposure(Number(this.exposureInput.value));
      this.user.draw();
      this.exposureText.value = `${Number(this.exposureInput.value) >= 0 ? "+" : ""}${this.exposureInput.value}`;
      this.queueFrame(null, false);
    });
    this.truthButton.addEventListener("click", () => this.setTruth(!this.truthOn));
    this.envSelect.addEventListener("change", () => this.setEnvironment(this.envSelect.value));
    this.sliceView.input.addEventListener("change", () => this.setSlice(this.sliceView.input.checked));
    this.lobe3d.input.addEventListener("change", () => this.setLobe3d(this.lobe3d.input.checked));
    this.mapInput.addEventListener("change", () => this.mapInput.files[0] && this.openHdr(this.mapInput.files[0]));
    this.start();
  }

  /** A context and the renderer, or the reason there is none. */
  start() {
    const { gl, why } = makeContext(this.canvas);
    if (!gl) return this.fail(`No live GPU view: ${why}. The server's sphere panel shows this model instead.`);
    this.gl = gl;
    this.canvas.addEventListener("webglcontextlost", (ev) => {
      ev.preventDefault();                 // lets the browser restore it
      this.ok = false;
      this.renderer = null;
      this.say(`The GPU context was lost (a shader ran too long, or the GPU was reset); restoring it…`, "error");
    });
    this.canvas.addEventListener("webglcontextrestored", () => {
      this.build();
      this.modelKey = null;
      if (this.state) this.sync(this.state);
    });
    this.build();
    this.dragHandlers();
  }

  build() {
    try {
      this.renderer = new SphereRenderer(this.gl, SIZE);
      this.renderer.exposure = Number(this.exposureInput.value);
      this.user.setExposure(this.renderer.exposure);
      this.ok = true;
    } catch (e) {
      this.fail(`No live GPU view: ${e.message}. The server's sphere panel shows this model instead.`);
    }
  }

  fail(why) {
    this.ok = false;
    this.failed = true;
    this.say(why, "error");
    this.section.classList.add("gpu-missing");
    this.onFallback?.(why);
  }

  say(text, kind = "") {
    this.message.textContent = text;
    this.message.className = `gpu-message ${kind}`;
  }

  /** The page's state changed: the model (fetch its code when it is another one), the
   * light (unless being dragged here). */
  sync(state) {
    this.state = state;
    if (!this.renderer) return;
    if (!this.dragging) {
      this.renderer.setLight(direction(state.theta_i_deg, state.phi_i_deg));
      this.user.setLight(this.renderer.light);
    }
    const family = fam.byName.get(state.model || fam.default);
    if (!this.fixedModel && family && family.shader === false) {   // /models: no shader for it
      this.modelKey = null;
      this.say(`No GPU shader for the ${family.label} yet (/api/v1/code writes the families `
        + "marked shader in /api/v1/models); the server's sphere panel draws it.");
      return;
    }
    const model = this.fixedModel || modelQuery(state);
    const key = query(model);
    if (key !== this.modelKey) {
      this.modelKey = key;
      this.loadModel(model, key);
    } else this.queueFrame(null, true);
  }

  /** The model's code from /code: one request in flight at a time (a slider's burst of
   * moves asks again only for the newest model when it returns); never aborted. */
  async loadModel(model, key) {
    if (this.codeInflight) { this.codeWanted = [model, key]; return; }
    this.codeInflight = true;
    let body, failure = null;
    try {
      const res = await fetch(`${API}/code?${query({ ...model, lang: "glsl", form: "uniform", format: "json" })}`);
      body = await res.json().catch(() => null);
      if (!res.ok || !body) failure = apiMessage(body, res);
    } catch (e) {
      failure = e.message;
    }
    this.codeInflight = false;
    const wanted = this.codeWanted;
    this.codeWanted = null;
    if (wanted && wanted[1] !== key) return this.loadModel(...wanted);
    if (failure !== null) {
      if (key !== this.modelKey) return;
      this.model = null;
      this.say(`No GPU shader for this model: ${failure} The server's sphere panel shows it.`, "error");
      return;
    }
    if (key !== this.modelKey || !this.renderer) return;
    try {
      if (this.renderer.setSource(structure(body.code))) this.compiles++;
    } catch (e) {
      this.model = null;
      this.say(e instanceof ShaderError ? `The generated shader failed here: ${e.message}` : String(e), "error");
      return;
    }
    this.model = model;
    // a Kulla-Conty shader's data texture (BRDF_DATA) and a fit's uniform block (BRDF_TABLES)
    // are bound like uniforms (gl.js setUniforms)
    body.uniforms = { ...body.uniforms, ...(body.textures || {}), ...(body.blocks || {}) };
    this.code = body;
    this.renderer.uniforms = body.uniforms;
    this.say(`Generated GLSL, ${body.lines} lines; ${this.compiles} compile${this.compiles === 1 ? "" : "s"} so far.`);
    this.queueFrame(null, true);
  }

  /** Draw at the next animation frame; `inputTime` (an event's timeStamp) is measured to
   * the finished frame; `changed`: the frame differs, so the truth is stale. */
  queueFrame(inputTime, changed) {
    if (inputTime !== null && this.inputTime === null) this.inputTime = inputTime;
    if (changed) this.truthStale();
    if (this.frameQueued) return;
    this.frameQueued = true;
    requestAnimationFrame(() => this.frame());
  }

  frame() {
    this.frameQueued = false;
    if (!this.renderer || !this.model || this.gl.isContextLost()) return;
    this.renderer.draw();
    this.user.setLight(this.renderer.light);
    this.user.draw();
    this.envRestart();
    this.sliceDraw();
    this.lobe3dDraw();
    this.legend();
    this.draws++;
    if (this.inputTime !== null) {
      // one pixel read back: the frame is finished, not merely queued
      this.gl.readPixels(0, 0, 1, 1, this.gl.RGBA, this.gl.UNSIGNED_BYTE, new Uint8Array(4));
      this.timings.push(performance.now() - this.inputTime);
      if (this.timings.length > TIMINGS_KEPT) this.timings.shift();
      this.inputTime = null;
    }
  }

  dragHandlers() {
    const c = this.canvas;
    const aim = (ev) => {
      const box = c.getBoundingClientRect();
      const x = ((ev.clientX - box.left) / box.width) * 2 - 1, y = 1 - ((ev.clientY - box.top) / box.height) * 2;
      const [theta, phi] = lightAt(x, y);
      this.dragLight = [theta, phi];
      this.renderer?.setLight(direction(theta, phi));
      this.truthStale();
      // drawn here, not at the next animation frame, and at most once per display frame
      // (the light of later moves in that frame waits for the next one)
      if (this.inputTime === null) this.inputTime = ev.timeStamp;
      if (this.drawnThisFrame) return this.queueFrame(null, false);
      this.drawnThisFrame = true;
      requestAnimationFrame(() => { this.drawnThisFrame = false; });
      this.frame();
    };
    c.addEventListener("pointerdown", (ev) => {
      if (ev.button !== 0 || !this.renderer) return;
      ev.preventDefault();
      this.dragging = true;
      c.setPointerCapture?.(ev.pointerId);
      aim(ev);
    });
    // pointerrawupdate (Chromium, secure contexts) comes as the input arrives; pointermove
    // waits for the next frame's start (up to 16.7 ms, half of that on average)
    const moveEvent = "onpointerrawupdate" in window ? "pointerrawupdate" : "pointermove";
    c.addEventListener(moveEvent, (ev) => { if (this.dragging) aim(ev); });
    const end = () => {
      if (!this.dragging) return;
      this.dragging = false;
      if (this.dragLight) this.onLight?.(...this.dragLight);
    };
    c.addEventListener("pointerup", end);
    c.addEventListener("pointercancel", end);
  }

  // ---------------------------------------------------------- environment ----
  /** The second sphere under a procedural environment ("" for none), progressive. */
  setEnvironment(name) {
    this.envName = name;
    this.envCanvas.hidden = this.envText.hidden = !name;
    if (!name) return;
    if (!this.envContext()) return;
    this.envSphere.env = name;
    this.envRestart();
  }

  envLabel() { return this.envName === MAP ? this.mapName : this.envName; }

  /** The environment sphere's own WebGL2 context, made once; false (and said) if none. */
  envContext() {
    if (this.envSphere) return true;
    const { gl, why } = makeContext(this.envCanvas);
    if (!gl) { this.envText.textContent = `No environment sphere: ${why}.`; return false; }
    this.envSphere = new EnvSphere(gl, SIZE);
    return true;
  }

  /** A Radiance .hdr file (picked here, or handed over by the page: openHdr(file)): read
   * and checked by the server, its cells drawn under the GPU sphere as the environment
   * "your .hdr". A file the server refuses is said with its reason; the rest stands. */
  async openHdr(file) {
    this.say(`Reading ${file.name}…`);
    let res, body;
    try {
      res = await fetch(`${API}/environments/hdr?format=f32&map_width=${MAP_WIDTH}`,
                        { method: "POST", body: file, headers: { "Content-Type": "application/octet-stream" } });
      body = res.ok ? await res.arrayBuffer() : await res.json().catch(() => null);
    } catch (e) {
      this.say(`${file.name}: ${e.message}`, "error");
      return false;
    }
    if (!res.ok) {                                      // said where the accumulation's report does not overwrite it
      this.say(`${file.name}: ${apiMessage(body, res)}`, "error");
      return false;
    }
    const [height, width] = res.headers.get("X-Map-Shape").split(",").map(Number);
    if (!this.envContext()) return false;
    this.envSphere.setMap({ width, height, rgb: new Float32Array(body) });
    this.say(`${file.name}: ${width} × ${height} cells under the environment sphere.`);
    this.mapName = file.name;
    Object.assign(this.mapOption, { hidden: false, disabled: false, text: `${file.name} (${width} × ${height} cells)` });
    this.envSelect.value = MAP;
    this.envInputKey = null;                            // another map under the same name
    this.setEnvironment(MAP);
    return true;
  }

  /** Accumulation from nothing when the model, its values, the light or the environment
   * changed (an exposure only redraws the mean): coarse while the input keeps changing
   * (a drag; changes closer than SETTLE_MS), at full size once it settles. */
  envRestart() {
    const e = this.envSphere;
    if (!this.envName || !e || !this.code || !this.model) return;
    try {
      e.setSource(structure(this.code.code));
    } catch (err) {
      this.envText.textContent = `The environment sphere cannot compile this model: ${err.message}`;
      return;
    }
    e.exposure = this.renderer.exposure;
    const input = [e.source, JSON.stringify(this.code.uniforms), this.renderer.light.join(), this.envName].join("\n");
    if (input === this.envInputKey && e.samples) { e.show(); return; }
    this.envInputKey = input;
    e.uniforms = this.code.uniforms;
    e.key = this.renderer.light;
    const now = performance.now();
    const preview = this.envPreview && (this.dragging || now - this.envChanged < SETTLE_MS);
    this.envChanged = now;
    if (this.inputTime !== null && this.envInput === null) this.envInput = this.inputTime;
    this.envBegin(preview);
    if (preview) {
      clearTimeout(this.envSettle);
      this.envSettle = setTimeout(() => this.envSettled(), SETTLE_MS);
    }
  }

  envBegin(preview) {
    this.envSphere.reset(preview);
    this.envStart = performance.now();
    this.envReference = null;
    this.envHistory = [];
    this.envStats = null;
    if (preview) this.envText.textContent = `Under ${this.envLabel()}: a ${PREVIEW_SIZE}² preview while the input changes…`;
    if (!this.envLoop) this.envLoop = requestAnimationFrame(() => this.envFrame());
  }

  /** The input has rested SETTLE_MS (or the drag ended): accumulate at full size. */
  envSettled() {
    const e = this.envSphere;
    if (!e || !e.preview) return;
    if (this.dragging || performance.now() - this.envChanged < SETTLE_MS) {
      this.envSettle = setTimeout(() => this.envSettled(), SETTLE_MS);
      return;
    }
    this.envBegin(false);
  }

  envFrame() {
    this.envLoop = 0;
    const e = this.envSphere;
    if (!this.envName || !e || e.gl.isContextLost()) return;
    e.step();
    const now = performance.now();
    if (this.envInput !== null) {
      // one pixel read back: the frame is finished, not merely queued
      e.gl.readPixels(0, 0, 1, 1, e.gl.RGBA, e.gl.UNSIGNED_BYTE, new Uint8Array(4));
      this.envTimings.push(performance.now() - this.envInput);
      if (this.envTimings.length > TIMINGS_KEPT) this.envTimings.shift();
      this.envInput = null;
    }
    this.envFrames.push({ t: now, preview: e.preview });
    if (this.envFrames.length > TIMINGS_KEPT) this.envFrames.shift();
    const done = e.samples >= ENV_MAX_SAMPLES;
    if (!e.preview && (e.frames % ENV_REPORT_FRAMES === 0 || done)) this.envReport();
    if (!done) this.envLoop = requestAnimationFrame(() => this.envFrame());
  }

  envReport() {
    const st = this.envSphere.stats();
    if (!st) return;
    this.envStats = { ...st, seconds: (performance.now() - this.envStart) / 1000 };
    this.envHistory.push({ seconds: this.envStats.seconds, samples: st.samples, relative: st.relative });
    const ref = this.envReference?.noise;
    const pct = (x) => `${(100 * x).toPrecision(2)} %`;
    const reached = (level) => this.envHistory.find((h) => h.relative <= level);
    const server = ref ? reached(ref.relative) : null, five = reached(ENV_NOISE_GOAL);
    this.envText.textContent = `Under ${this.envLabel()}: ${st.samples} sample pairs per pixel in ${this.envStats.seconds.toFixed(1)} s; `
      + `noise ±${pct(st.relative)} (each pixel's standard error from its own samples, RMS over the disk, over the mean`
      + (five ? `; ≤ ${pct(ENV_NOISE_GOAL)} after ${five.seconds.toFixed(1)} s` : "") + "); "
      + `mean luminance ${st.mean.toPrecision(5)} ± ${st.error.toExponential(1)}`
      + (ref ? `. The server's (${this.envReference.samples.per_pixel} samples a pixel, MIS): noise ±${pct(ref.relative)}`
        + (server ? ` (reached here after ${server.seconds.toFixed(1)} s)` : "")
        + `, mean ${ref.mean_radiance.toPrecision(5)} ± ${ref.mean_radiance_error.toExponential(1)}, difference `
        + `${(Math.abs(st.mean - ref.mean_radiance) / Math.hypot(st.error, ref.mean_radiance_error)).toFixed(1)} σ.` : ".");
    if (this.envName === MAP) this.envText.textContent += ` (${this.mapName}: the server's sphere does not draw a user's map yet, so no comparison.)`;
    else if (!ref && !this.envAsked && this.envStats.seconds > 2) this.envAskServer();
  }

  async envAskServer() {
    this.envAsked = true;
    const [x, y, z] = this.renderer.light;
    const theta = Math.acos(Math.min(1, z)) * 180 / Math.PI, phi = Math.atan2(y, x) * 180 / Math.PI;
    const q = query({ ...this.model, environment: this.envName, n: SIZE, samples: 16, theta_i_deg: theta, phi_i_deg: phi });
    const start = this.envStart;
    try {
      const res = await fetch(`${API}/sphere_env?${q}`);
      const body = await res.json();
      if (res.ok && start === this.envStart) { this.envReference = body; this.envReport(); }
    } catch { /* the comparison is left out; the sphere stands */ }
    this.envAsked = false;
  }

  // ------------------------------------------------- slice and 3-D lobe ----
  /** The θ_h–θ_d slice beside the spheres (sliceview.js), or not. */
  /** Which column is which once there are two (the page's model, the user's BRDF), and
   * how to read the slice: said above the views, only while it has something to say. */
  legend() {
    const parts = [];
    if (this.user.name && !this.user.canvas.hidden) parts.push(`Left: the page's model · right: your BRDF (${this.user.name}).`);
    if (this.sliceView.input.checked) parts.push("Slice: θ_h 0→90° left to right, θ_d 0→90° bottom to top, colour log₁₀ f.");
    const text = parts.join(" ");
    if (this.legendLine.textContent !== text) this.legendLine.textContent = text;
    this.legendLine.hidden = !text;
  }

  setSlice(on) {
    this.sliceView.setOn(on, this.truthOn);
    this.sliceDraw();
    this.legend();
    if (on) this.truthStale();
  }

  sliceDraw() {
    if (this.model) this.sliceView.draw(this.code, this.code && structure(this.code.code), this.user);
  }

  setLobe3d(on) {
    this.lobe3d.setOn(on);
    this.lobe3dDraw();
    if (on) this.truthStale();
  }

  /** The 3-D lobes (lobe3dview.js) for the model, the user's BRDF and the light. */
  lobe3dDraw() {
    if (!this.code || !this.model || !this.renderer) return;
    const why = this.lobe3d.update({ glsl: structure(this.code.code), uniforms: this.code.uniforms }, this.user, this.renderer.light);
    if (why) this.say(why, "error");
  }

  // ---------------------------------------------------------------- truth ----
  setTruth(on) {
    this.truthOn = on;
    this.truthButton.textContent = on ? "Truth: on" : "Truth: off";
    this.truthButton.setAttribute("aria-pressed", String(on));
    this.diffCanvas.hidden = !on;
    this.truthText.hidden = !on;
    this.sliceView.showTruth(on);
    this.lobe3d.showTruth(on);
    if (on) this.truthStale();
    else this.truthToken++;
  }

  truthStale() {
    if (!this.truthOn) return;
    this.truth = null;
    this.sliceView.truth = null;
    this.lobe3d.truthStale();
    clearTimeout(this.truthTimer);
    this.truthToken++;
    this.truthText.textContent = "Comparing with the server's float64 frame…";
    this.truthTimer = setTimeout(() => this.checkTruth(), TRUTH_DELAY_MS);
  }

  async checkTruth() {
    if (!this.renderer || !this.model || this.dragging) return;
    this.renderer.render();
    const gpu = this.renderer.read();
    const light = this.renderer.light, model = this.model;
    const token = ++this.truthToken;           // a later change makes this answer stale
    this.sliceDraw();                          // the slice of this model, drawn before it is read
    const current = () => token === this.truthToken;
    const sliceDone = this.sliceView.checkTruth(model, current);
    this.lobe3dDraw();                         // the lobe of this model and light, likewise
    const lobeDone = this.lobe3d.checkTruth(model, current);
    let ref;
    try {
      ref = await referenceFrame(model, light, SIZE);
    } catch (e) {
      if (token === this.truthToken) this.truthText.textContent = `No reference frame: ${e.message}`;
      return;
    }
    if (token !== this.truthToken) return;
    const r = compare(gpu, ref, SIZE, light);
    this.truth = { max: r.max, mean: r.mean, at: r.at, pixels: r.pixels, disk: r.disk, absPeak: r.absPeak,
                   nonFinite: r.nonFinite, floor: r.floor };
    const ctx2d = this.diffCanvas.getContext("2d");
    ctx2d.putImageData(new ImageData(diffImage(r.diff, SIZE), SIZE, SIZE), 0, 0);
    this.truthText.textContent = sphereTruthText(r);
    await Promise.all([sliceDone, lobeDone]);
  }

  /** For tests and bench/gpu_sphere.py. */
  hook() {
    const self = this;
    return {
      get ok() { return self.ok && !!self.model; },
      get compiles() { return self.compiles; },
      get draws() { return self.draws; },
      get timings() { return self.timings.slice(); },
      get truth() { return self.truth; },
      get sliceTruth() { return self.sliceView.truth; },
      setSlice: (on) => { self.sliceView.input.checked = on; self.setSlice(on); },
      setLobe3d: (on) => self.setLobe3d(on),
      /** The 3-D lobe's truth: its statistics, the float32 directions and light compared. */
      get lobe3dTruth() { return self.lobe3d.truth; },
      /** The 3-D lobes' radii f·cos θ_o at [[θ_o, φ_o], …] (degrees), read back from the
       * vertex shader: {registry, user}; the orbit turned by a drag of (dx, dy) pixels. */
      lobe3d: (angles) => self.lobe3d.radii(angles),
      turnLobe3d: (dx, dy) => self.lobe3d.turn(dx, dy),
      get lobe3dDraws() { return self.lobe3d.draws; },
      /** The user's BRDF's slice as drawn: f (RGB per pixel, rows θ_d from 0) and n·l, n·v
       * of its float32 directions; null when it is not drawn. */
      userSlice() {
        const r = self.sliceView.user.read();
        if (!r) return null;
        const pick = (a, k0, step) => Array.from({ length: a.length / step }, (_, p) => a[step * p + k0]);
        return { rgb: [0, 1, 2].map((c) => pick(r.f, c, 4)), nl: pick(r.l, 2, 4), nv: pick(r.v, 2, 4) };
      },
      get message() { return self.message.textContent; },
      get model() { return self.model; },
      get env() { return self.envStats ? { ...self.envStats, reference: self.envReference?.noise ?? null } : null; },
      get envHistory() { return self.envHistory.slice(); },
      get envTimings() { return self.envTimings.slice(); },
      get envFrames() { return self.envFrames.slice(); },
      get envPreviewing() { return !!self.envSphere?.preview; },
      /** An image of `pairs` sample pairs a pixel from random numbers seeded by `seed`, at
       * full size, drawn now (the progressive loop stopped meanwhile and restarted after):
       * each disk pixel's mean luminance and the stated statistics. */
      envIndependent(seed, pairs) {
        const e = self.envSphere;
        cancelAnimationFrame(self.envLoop);
        self.envLoop = 0;
        e.seed = seed;
        e.reset(false);
        while (e.samples < pairs) e.step();
        const out = { means: e.pixelMeans(), stats: e.stats() };
        e.seed = 0;
        self.envBegin(false);
        return out;
      },
      /** The coarse accumulation while the input changes: on (the page's) or off (bench). */
      set envPreview(on) { self.envPreview = on; },
      setEnvironment: (name) => { self.envSelect.value = name; self.setEnvironment(name); },
      /** A .hdr's bytes (an array of numbers) opened as if picked: true when drawn. */
      openHdr: (bytes, name = "test.hdr") => self.openHdr(new File([new Uint8Array(bytes)], name)),
      get code() { return self.code; },
      clearTimings() { self.timings.length = 0; self.envTimings.length = 0; self.envFrames.length = 0; },
      /** Draw this model query instead of the page's (until null): resolves when drawn
       * or failed, with the panel's message. */
      async load(model) {
        self.fixedModel = model;
        const m = model || modelQuery(self.state);
        self.modelKey = query(m);
        await self.loadModel(m, self.modelKey);
        await new Promise((r) => requestAnimationFrame(() => requestAnimationFrame(r)));
        return self.message.textContent;
      },
      setTruth: (on) => self.setTruth(on),
      /** The truth of the current frame now (no wait for the toggle's delay). */
      async truthNow() {
        self.setTruth(true);
        clearTimeout(self.truthTimer);
        await self.checkTruth();
        return self.truth;
      },
    };
  }
}
