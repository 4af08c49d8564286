/* The panels: one per view of GET /api/v1/views, each with its own toggles, its
 * figure, one sentence of what it shows, and its export buttons. A panel knows how to
 * ask for its figure (request) and how to draw an answer (receive, draw); when to do
 * either is the scheduler's business. A view that does not take the chosen model
 * (GET /api/v1/models lists the views that draw each family) says so instead.
 */
import { API, el, richText, replaceText, apiMessage, query, setIf } from "../base/dom.js";
import { reg, modelQuery, compact, isAnisotropic } from "../state/model.js";
import { ctx } from "../base/ctx.js";
import { compareModels } from "../state/pins.js";
import { hintOf, viewTitle, fieldRole, isHeavy, overlayable, layoutOf } from "../state/views.js";
import { panelFields, localControl, fieldApplies } from "../controls/panelcontrols.js";
import { fitLayout, reuseLayout, compactLegend, titleText, PLOT_CONFIG } from "./layout.js";
import { Readouts } from "./readouts.js";
import { exportBar } from "./exports.js";
import { Chart } from "../chart/chart.js";
import { drawsFigure } from "../chart/traces.js";
import { fam, viewTakes, whyNot, otherFamily, familyAnisotropic } from "../state/families.js";
import { Refiner, serverNote } from "./refine.js";

const LOADING_DELAY_MS = 300;

// D, Λ/G1 and E(μ) are taken at one azimuth: the plane of incidence's when anisotropic.
const anisotropic = (s) => (otherFamily(s) ? familyAnisotropic(s) : isAnisotropic(s));
const sliceAzimuth = (s) => (anisotropic(s) ? { phi_deg: s.phi_i_deg } : {});

/** While a slider is held, the heavy images come coarser (about half the resolution
 * each way; the samples a quarter): full resolution follows on release. */
function heldResolution(view) {
  const q = {};
  for (const f of view.fields) {
    if (fieldRole(f) !== "resolution" || f.type !== "integer" || !Number.isFinite(f.default)) continue;
    const factor = view.name === "samples" ? 4 : 2;
    q[f.name] = Math.max(f.minimum ?? 2, Math.round(f.default / factor));
  }
  return q;
}

export class Panel {
  constructor(view, { onChange, onPin, onTails }) {
    this.view = view;
    this.name = view.name;
    this.hint = hintOf(view.name);
    this.refiner = this.hint.refine ? new Refiner(this) : null;    // refined at rest (refine.js)
    Object.assign(this, { inflight: null, dirty: false, drawing: null, drawnKey: null, inView: false,
                          drawn: false, error: null, loadingTimer: 0, chart: null, figure: null,
                          readouts: new Readouts() });
    const hid = `h-${view.name}`;
    this.heading = el("h2", { id: hid }, richText(viewTitle(view)));
    this.sub = el("span", { class: "sub" });
    this.heading.append(" ", this.sub);
    const tools = el("div", { class: "panel-tools" }, ...panelFields(view).map((f) => localControl(view, f, onChange)));
    this.status = el("div", { class: "panel-status", role: "status", "aria-live": "polite" });
    this.div = el("div", { class: "plot", id: `plot-${view.name}` });
    this.modelNote = el("p", { class: "model-note", id: `note-${view.name}`, role: "note", hidden: true });
    const caption = el("p", { class: "caption", id: `cap-${view.name}` }, richText(this.hint.caption || view.summary || ""));
    const bar = exportBar(() => ({ kind: view.name, params: compact(this.params(ctx.state)), figure: this.exportable(),
                                   title: viewTitle(view) }), (k, t) => this.report?.(k, t));
    bar.classList.add("panel-export");
    const buttons = el("div", { class: "panel-buttons" });
    if (this.hint.pin || this.hint.tails) {
      const pinBar = el("div", { class: "pin-bar", role: "group", "aria-label": "Compare models" });
      if (this.hint.pin) {
        this.pinButton = el("button", { type: "button", class: "export pin-btn", "data-action": "pin", text: "Pin",
                                        title: "Keep the current model as a curve on every curve panel" });
        this.pinButton.addEventListener("click", onPin);
        pinBar.append(this.pinButton);
      }
      if (this.hint.tails) {
        const tails = el("button", { type: "button", class: "export pin-btn", "data-action": "tails", text: "Compare tails",
                                     title: "Pin GGX, Beckmann and Blinn-Phong at the current α and show D on a log scale" });
        tails.addEventListener("click", onTails);
        pinBar.append(tails);
      }
      buttons.append(pinBar);
    }
    buttons.append(bar);
    this.actions = el("div", { class: "panel-actions" }, tools, buttons);
    this.wrap = el("div", { class: "plot-wrap" }, this.div, this.status);
    const layout = layoutOf(view);
    this.section = el("section", { class: `panel${layout !== "half" ? " panel-wide" : ""}${layout === "strip" ? " panel-short" : ""}`,
                                   "data-panel": view.name, "aria-labelledby": hid, "aria-describedby": caption.id, hidden: true },
      el("header", { class: "panel-head" }, this.heading, this.actions), this.wrap, this.modelNote, caption);
  }

  shown(s = ctx.state) { return s.show.includes(this.name); }
  takesModel(s = ctx.state) { return viewTakes(this.name, s); }
  /** Shown and drawing this model (in view or not): its requests in flight are kept. */
  shows() { return this.shown() && this.takesModel(); }
  /** Shows it and is in view: it asks for what it draws. */
  wanted() { return this.shows() && this.inView; }

  /** A view that does not take the chosen model: a note in place of the plot, which
   * stays as it was drawn, for when the model it takes is chosen again. */
  syncModel() {
    const off = !this.takesModel();
    if (off === !this.modelNote.hidden) return;
    const takers = fam.list.filter((f) => !f.views || f.views.includes(this.name));
    this.modelNote.textContent = off ? `${viewTitle(this.view)} is for the `
      + `${takers.map((f) => f.label.toLowerCase()).join(" or the ")} only. `
      + `${whyNot(this.name, ctx.state)} Choose “${takers[0]?.label}” under Model to see it.` : "";
    this.modelNote.hidden = !off;
    this.wrap.hidden = this.actions.hidden = off;
    this.sub.hidden = off;
    this.section.classList.toggle("panel-off", off);   // a note needs no plot's height
  }
  pinned(s) { return s.pins.length > 0 && !!this.hint.pin && overlayable(this.view); }
  overlaid(s) {
    return !!s.vary && overlayable(this.view) && this.view.vary.includes(s.vary) && !this.pinned(s);
  }

  /** The figure's parameters that are not the model's (the "view" of a POST). */
  viewParams(s) {
    const q = {};
    const geometry = new Set(reg.models.geometry.map((p) => p.name));
    for (const f of this.view.fields) if (geometry.has(f.name)) q[f.name] = s[f.name];
    if (this.hint.slice) Object.assign(q, sliceAzimuth(s));
    for (const [key, loc] of ctx.locals) {
      if (loc.view === this.name && s[key] !== loc.field.default && fieldApplies(this.name, loc.field, s)) q[loc.field.name] = s[key];
    }
    // an albedo method that a model drawn (the current one, pinned ones) does not take
    // (its family's albedo_methods) gives way to the first method they all take
    const drawn = [s.model, ...(this.pinned(s) ? s.pins.map((pin) => pin.model ?? fam.default) : [])];
    const methods = drawn.map((name) => fam.byName.get(name)?.albedo_methods).filter(Boolean)
      .reduce((all, m) => (all ? all.filter((x) => m.includes(x)) : m), null);
    if (methods?.length && q.method !== undefined && !methods.includes(q.method)) q.method = methods[0];
    if (this.overlaid(s)) Object.assign(q, { vary: s.vary, values: s.values });
    for (const [k, v] of Object.entries(s.extra || {})) if (this.view.fields.some((f) => f.name === k)) q[k] = v;
    return q;
  }
  params(s) { return { ...modelQuery(s), ...this.viewParams(s) }; }

  url(s = ctx.state) {
    const held = ctx.held && isHeavy(this.view) ? heldResolution(this.view) : {};
    return `${API}/figures/${this.name}${this.overlaid(s) ? ".json" : ""}?${query({ ...this.params(s), ...held })}`;
  }

  /** {key, url, init}: key is what the panel would draw. */
  request(s = ctx.state) {
    const accept = { Accept: "application/json" };
    if (this.pinned(s)) {
      const url = `${API}/figures/${this.name}`;
      const body = JSON.stringify({ ...compareModels(s), view: compact(this.viewParams(s)) });
      return { key: `POST ${url} ${body}`, url,
               init: { method: "POST", headers: { ...accept, "Content-Type": "application/json" }, body } };
    }
    const url = this.url(s);
    return { key: url, url, init: { headers: accept } };
  }

  /** Goes out with the other panels' GETs of the same change (batch.js): a figure GET,
   * not a heavy image, which would hold the curves back. */
  batchable(req) { return !req.init.method && !isHeavy(this.view) && req.url.startsWith(`${API}/figures/`); }

  /** Plotly keeps zoom and camera while this stays the same: per panel and toggle. */
  uirevision(s) {
    const own = [...ctx.locals].filter(([, l]) => l.view === this.name && l.field.type === "boolean").map(([k]) => `${k}:${s[k]}`);
    return [this.name, ...own, this.overlaid(s) ? s.vary : "", this.pinned(s) ? "pins" : ""].join("|");
  }

  receive(req, res, body) {
    const s = ctx.state;
    if (!res.ok) throw new Error(apiMessage(body, res));
    if (!body || !Array.isArray(body.data)) throw new Error("The server sent no figure.");
    const compare = req.init.method === "POST";
    if (compare) compactLegend(body.data);
    const [title, note = ""] = titleText(body.layout).split(/<br\s*\/?>/i);
    const heading = compare ? `${JSON.parse(req.init.body).models.length} models`
      : this.overlaid(s) ? `comparing ${s.vary} = ${String(s.values).split(",").join(", ")}`
      : title.includes(" — ") ? title.slice(title.indexOf(" — ") + 3) : title;
    // a sampled image states its noise and samples in the title's second line: shown
    // before the heading's parameters (the refinement at rest states its own: refine.js)
    const sampled = this.refiner && note ? serverNote(note) : "";
    return { data: body.data, layout: body.layout || {}, uirevision: this.uirevision(s),
             sub: sampled ? `${sampled} · ${heading}` : heading, heading };
  }

  /** A curve figure is drawn by the panel's chart at once (its canvas is painted in
   * the chart's worker: the page's frame need not be waited for), or in the next
   * animation frame when it drew in this one: at most one draw a frame, the newest
   * answer. Null for a figure the chart does not draw (the scheduler draws it in its
   * own frame). */
  quick(drawable) {
    if (!this.chart || this.error || !drawsFigure(drawable)) return null;
    this.toDraw = drawable;
    const frame = () => document.timeline.currentTime;
    const wait = this.drawnIn === frame() ? new Promise((r) => requestAnimationFrame(r)) : Promise.resolve();
    this.writing ||= wait.then(() => {
      const d = this.toDraw;
      this.toDraw = this.writing = null;
      this.drawnIn = frame();
      return this.draw(d);
    }).catch((e) => this.fail(e.message || String(e)));
    return this.writing;
  }

  /** Draws an answer: curves on the panel's chart (chart/chart.js), anything else (an
   * image, a heat map, the 3-D lobe, a table) with Plotly. A failure is a rejection. */
  async draw(drawable) {
    const { data, layout, uirevision, sub } = drawable;
    this.refiner?.drawn(drawable);
    this.setSub(sub);
    this.figure = { data, layout };
    if (drawsFigure(drawable)) {
      if (!this.chart) {
        if (this.div.layout) Plotly.purge(this.div);
        this.chart = new Chart(this.div);
      }
      this.shown_();
      const { paintedAt } = await this.chart.draw(this.figure, { revision: uirevision });
      this.announce(paintedAt);
      return;
    }
    if (this.chart) {
      this.chart.dispose();
      this.chart = null;
    }
    return this.drawn_(Plotly.react(this.div, data, reuseLayout(this, fitLayout(layout), uirevision), PLOT_CONFIG));
  }

  /** A figure the data module (app/data.js) draws over this panel's: the data beside
   * the model, drawn as the panel draws; not announced (it follows the panel's own). */
  overlay(figure) {
    this.figure = figure;
    if (this.chart && drawsFigure(figure)) return this.chart.draw(figure, { revision: this.chart.revision });
    return Plotly.react(this.div, figure.data, figure.layout, PLOT_CONFIG);
  }

  /** What an image export draws in this browser when the server cannot (exports.js):
   * the figure as the server made it, title and all, or the Plotly plot as drawn. */
  exportable() {
    if (!this.figure) return null;
    return this.chart ? { data: this.figure.data, layout: fitLayout(this.figure.layout, { keepTitle: true }) } : this.div;
  }

  /** A slider grabbed: a refinement at rest stops (refine.js). */
  grab() { this.refiner?.check(); }

  /** The slider let go: readouts held back while it moved are shown. */
  release() { this.readouts.flush(); }

  /** The heading's parameters (a readout: while a slider is held, a few times a second). */
  setSub(sub) {
    this.readouts.show("sub", () => {
      if (this.subText === sub) return;
      this.subText = sub;
      replaceText(this.sub, richText(sub));
    }, ctx.held);
  }

  shown_() {
    this.drawn = true;
    this.error = null;
    this.setStatus(null);
    this.section.classList.toggle("empty", false);     // remove() would re-set an unchanged class
  }

  /** One event per finished draw (the benchmark and the tests count them); paintedAt:
   * when a chart's canvas was painted (ms since the epoch; its worker's clock, read a
   * task before this event can run), else the event's own time. */
  announce(paintedAt = performance.timeOrigin + performance.now()) {
    this.div.dispatchEvent(new CustomEvent("brdf-drawn", { detail: { paintedAt } }));
  }

  drawn_(promise) {
    this.shown_();
    return promise.then(() => this.announce());
  }

  fail(message) {
    clearTimeout(this.loadingTimer);
    this.error = message;
    this.setStatus("error", message);
    this.section.classList.toggle("empty", !this.drawn);
  }

  busy(text) { clearTimeout(this.loadingTimer); this.setStatus("loading", text); }   // asks again soon (scheduler.js)

  loading(on) {
    clearTimeout(this.loadingTimer);
    if (on) this.loadingTimer = setTimeout(() => this.setStatus("loading", "loading…"), LOADING_DELAY_MS);
    else if (this.status.classList.contains("loading")) this.setStatus(this.error ? "error" : null, this.error || "");
  }

  setStatus(kind, text = "") {
    setIf(this.status, "className", `panel-status${kind ? ` ${kind}` : ""}`);
    setIf(this.status, "textContent", text);
    this.section.classList.toggle("has-error", kind === "error");
  }
}
