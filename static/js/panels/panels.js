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
import { canAnimate, animateData, renameLegend, traceStyle, splitRanges, rangesFit, withHeadroom, withRanges,
         logAxes, sameTraces, rangeUpdate, HELD_FILL, HELD_HEADROOM } from "./fastdraw.js";
import { writePaths } from "./svgpaths.js";
import { drawHeld, endHeld, readyHeld, ownTask } from "./heldcanvas.js";
import { Readouts } from "./readouts.js";
import { decadesFor, scaleData, scaleRanges, baseLabels, labelsShift, writeLabels } from "./decades.js";
import { exportBar } from "./exports.js";
import { fam, viewTakes, whyNot, otherFamily, familyAnisotropic } from "../state/families.js";
import { Refiner, serverNote } from "./refine.js";

const LOADING_DELAY_MS = 300;
// After paths written directly, Plotly's own state is brought up to date (Panel.sync)
// when the plot is used (hover, resize, export), or once the page has been quiet this long.
const SYNC_IDLE_MS = 1500;
// a browser without requestIdleCallback (Safari before 18) gets a short timer
const whenIdle = (f) => (window.requestIdleCallback ? requestIdleCallback(f, { timeout: 2000 }) : setTimeout(f, 200));

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
                          drawn: false, error: null, loadingTimer: 0,
                          relayout: {},      // axis ranges to relay out in the next write (refit)
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
    this.div.addEventListener("pointerenter", () => this.sync());
    const bar = exportBar(() => {
      this.sync();                                    // its image export reads Plotly's state
      return { kind: view.name, params: compact(this.params(ctx.state)), div: this.div, title: viewTitle(view) };
    }, (k, t) => this.report?.(k, t));
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
    return { data: body.data, layout: fitLayout(body.layout || {}), uirevision: this.uirevision(s),
             sub: sampled ? `${sampled} · ${heading}` : heading, heading };
  }

  /** A data-only redraw (see fastdraw.js) when only the data moved; null otherwise.
   * While a slider is held, data that left a linear axis by decades is drawn rescaled on
   * the axes as they are, their labels moved (decades.js). */
  quick({ data, layout, uirevision, sub }, frame = () => new Promise((r) => requestAnimationFrame(r))) {
    if (!this.drawn || this.error || uirevision !== this.uirev) return null;
    const { ranges, rest } = splitRanges(layout);
    if (rest !== this.rest || (this.decades && !ctx.held)) return null;
    if (this.refitDue && !ctx.held) return this.refit({ data, layout, sub }, ranges, frame, "exact");
    if (Object.keys(this.relayout).length) {
      // new ranges wait for the next frame (refit): Plotly's axes are not yet what the
      // answer is measured against; the server's ranges hold its data
      return rangesFit(this.ranges, ranges) ? this.refit({ data, layout, sub }, ranges, frame) : null;
    }
    const fill = ctx.held ? HELD_FILL : undefined;
    const logs = logAxes(layout), openBelow = ctx.held ? logs : undefined;
    const fits = (shown, decades) => rangesFit(this.ranges, scaleRanges(ranges, decades, -1, logs), fill, openBelow)
      && canAnimate(this.div, shown, this.styles, fill);
    let decades = this.decades, shown = decades ? scaleData(data, decades) : data;
    if (!fits(shown, decades)) {
      if (!ctx.held) return this.refit({ data, layout, sub }, ranges, frame);
      decades = decadesFor(this.div, data, this.ranges, ranges);
      if (decades) {
        // an axis not shifted since Plotly drew it: its labels as drawn are the base
        this.labels = { ...baseLabels(this.div, Object.keys(decades).filter((k) => !this.labels?.[k]), this.ranges), ...this.labels };
        shown = labelsShift(this.labels, decades) ? scaleData(data, decades) : null;
      }
      if (!decades || !shown || !fits(shown, decades)) {
        if (!logs.size || this.decades) return null;
        // a log axis its decades cannot follow: relaid out with room at both ends
        this.labels = null;
        const moved = this.refit({ data, layout, sub }, ranges, frame, "held");
        if (moved) this.loose = true;
        return moved;
      }
    }
    const scaled = decades && Object.keys(decades).length ? decades : null;
    if (ctx.held && (scaled || !rangesFit(this.ranges, ranges))) this.loose = true;
    this.setSub(sub);
    this.styles = data.map(traceStyle);
    this.shown_();
    return this.writeInFrame(data, frame, shown, scaled);
  }

  /** New axis ranges and nothing else new (the same traces and layout, no rescaled
   * axes): the ranges are relaid out alone and the data written as a data-only redraw,
   * in one animation frame (~25 ms, where Plotly.react took 45–120 ms: the NDF's and
   * G1's full draws when a drag is let go were most of the time it took to settle);
   * null when more than the ranges changed. fit: "exact", the server's ranges as they
   * are (a drag let go: as a fresh page draws them); "held", with HELD_HEADROOM at both
   * ends of a log axis that whole decades cannot follow (labelled between decades: a
   * relayout, 17-40 ms, where its full draw took 45-120); else with headroom where they
   * moved. */
  refit({ data, layout, sub }, ranges, frame, fit = "moved") {
    if (this.decades || !sameTraces(data, this.styles)) return null;
    const drawn = this.rangesToDraw(fit, this.serverRanges, ranges, layout);
    const moved = Object.keys(drawn).filter((k) => !(this.ranges?.[k]?.[0] === drawn[k][0] && this.ranges?.[k]?.[1] === drawn[k][1]));
    Object.assign(this.relayout, rangeUpdate(reuseLayout(this, withRanges(layout, drawn), this.uirev), moved));
    Object.assign(this, { serverRanges: ranges, ranges: drawn, loose: false });
    this.setSub(sub);
    this.styles = data.map(traceStyle);
    this.shown_();
    return this.writeInFrame(data, frame);
  }

  /** The ranges to draw for the server's `ranges`, by `fit`: "exact", as they are (a
   * drag let go; so for every answer until the one still in flight is in); "held", with
   * HELD_HEADROOM at both ends of a log axis and where the others moved since `previous`;
   * "moved", with HEADROOM where they moved. */
  rangesToDraw(fit, previous, ranges, layout) {
    if (fit === "exact" && !this.inflight) this.refitDue = false;
    if (fit === "exact") return ranges;
    return fit === "held" ? withHeadroom(previous, ranges, HELD_HEADROOM, logAxes(layout)) : withHeadroom(previous, ranges);
  }

  /** Writes the newest data's paths in the animation frame `frame()` resolves in (one
   * write a frame however many answers land before it; a held slider's, in a task of
   * its own just after it: ownTask); Plotly draws it if the paths cannot take it
   * (Plotly's transition on its own axes). `shown`: the data as drawn on axes rescaled by `decades`. */
  writeInFrame(data, frame, shown = data, decades = null) {
    this.toWrite = { data, shown, decades };
    this.writing ||= new Promise((resolve) => frame().then(() => ctx.held && ownTask()).then(() => {
      const { data: d, shown: s, decades: j } = this.toWrite;
      this.toWrite = null;
      this.writing = null;
      if (Object.keys(this.relayout).length) {     // new ranges (refit): in this frame
        const update = this.relayout;
        this.relayout = {};
        Plotly.relayout(this.div, update).catch(() => {});
      }
      // a held slider's curves on the canvas over the plot (heldcanvas.js), else the SVG's
      const onCanvas = ctx.held && drawHeld(this.div, s);
      if (onCanvas || writePaths(this.div, s)) {
        if (!onCanvas) endHeld(this.div);
        if (this.labels) writeLabels(this.labels, j || {});
        this.decades = j;
        this.readouts.show("legend", () => renameLegend(this.div, d), ctx.held);
        this.div.data = d;        // what the plot shows, for readers of it; Plotly's own state follows in sync()
        this.stale = d;
        clearTimeout(this.syncTimer);
        this.syncTimer = setTimeout(() => this.sync({ idle: true }), SYNC_IDLE_MS);
        this.announce();
        resolve();
      } else if (!j && !this.decades) {        // axes as Plotly drew them: its own transition
        endHeld(this.div);
        this.readouts.drop("legend");          // Plotly names the traces
        resolve(animateData(this.div, d).then(() => this.announce()));
      } else {
        this.decades = this.labels = null;
        endHeld(this.div);
        this.readouts.drop("legend");
        resolve(Plotly.react(this.div, d, this.layout, PLOT_CONFIG).then(() => this.announce()));
      }
    }));
    return this.writing;
  }

  /** Plotly's state (read by hover, zoom, resize and its image export) brought to the
   * data shown, after paths were written directly; the pixels stay as they are (on
   * rescaled axes, Plotly draws the axes that they stand for). `idle`: called because
   * the page was quiet, which a slider held still is not: the hand may move again at any
   * moment, and the four redraws (20-50 ms each) would be in its way; it waits. */
  sync({ idle = false } = {}) {
    clearTimeout(this.syncTimer);
    if (!this.stale) return Promise.resolve();
    if (this.drawing || this.writing || (idle && ctx.held)) {   // a draw under way, or held: later
      this.syncTimer = setTimeout(() => this.sync({ idle }), SYNC_IDLE_MS);
      return Promise.resolve();
    }
    const data = this.stale;
    this.stale = null;
    if (this.decades) {
      this.ranges = scaleRanges(this.ranges, this.decades, 1, logAxes(this.layout));
      this.layout = withRanges(this.layout, this.ranges);
      this.layoutKey = null;
      this.decades = this.labels = null;
    }
    endHeld(this.div);
    this.readouts.drop("legend");
    return Plotly.react(this.div, data, this.layout, PLOT_CONFIG).catch(() => {});
  }

  /** A slider grabbed (or the page idle after a draw): a plot in view has its canvas for
   * a drag ready, at its size (heldcanvas.js). */
  grab() {
    this.refiner?.check();
    if (this.inView && this.drawn && !this.error) readyHeld(this.div);
  }

  /** The slider let go: axes left loose by the drag are fitted to the data again, to the
   * ranges the server gives, as a fresh page draws them (the panel asks again: refit). */
  release() {
    this.readouts.flush();
    if (this.loose) Object.assign(this, { drawnKey: null, refitDue: true });
    this.loose = false;
  }

  /** The heading's parameters (a readout: while a slider is held, a few times a second). */
  setSub(sub) {
    this.readouts.show("sub", () => {
      if (this.subText === sub) return;
      this.subText = sub;
      replaceText(this.sub, richText(sub));
    }, ctx.held);
  }

  draw(drawable) {
    const { data, layout, uirevision, sub } = drawable;
    this.refiner?.drawn(drawable);
    this.setSub(sub);
    this.styles = data.map(traceStyle);
    this.stale = this.decades = this.labels = null;
    this.relayout = {};
    clearTimeout(this.syncTimer);
    const { ranges, rest } = splitRanges(layout);
    const same = rest === this.rest && uirevision === this.uirev;
    const fit = ctx.held ? "held" : this.refitDue ? "exact" : "moved";
    const drawn = this.rangesToDraw(fit, same ? this.serverRanges : null, ranges, layout);
    Object.assign(this, { rest, uirev: uirevision, serverRanges: ranges, ranges: drawn, loose: ctx.held && same });
    endHeld(this.div);
    this.readouts.drop("legend");
    return this.drawn_(Plotly.react(this.div, data, reuseLayout(this, withRanges(layout, drawn), uirevision), PLOT_CONFIG));
  }

  shown_() {
    this.drawn = true;
    this.error = null;
    this.setStatus(null);
    this.section.classList.toggle("empty", false);     // remove() would re-set an unchanged class
  }

  // one event per finished draw, whichever way it was drawn (the benchmark counts them)
  announce() { this.div.dispatchEvent(new CustomEvent("brdf-drawn")); }

  drawn_(promise) {
    this.shown_();
    return promise.then(() => {
      this.announce();
      // the canvas a held slider draws on, made while the page is idle (else at the grab)
      if (!this.canvasDue) {
        this.canvasDue = true;
        whenIdle(() => { this.canvasDue = false; this.grab(); });
      }
    });
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
