/* A small canvas chart for the curve panels: one draw(figure) that paints the whole
 * figure in one go (axes, grid, curves) on a canvas, with its legend, axis titles and
 * notes as page text. Built for data that moves with a slider (uPlot's idea): drawing a
 * figure again costs a millisecond or two whatever changed, so there is one way to draw
 * and nothing to keep in step. The canvas is painted in a worker where the browser has
 * OffscreenCanvas (worker.js: the main thread then spends nothing on the pixels), else
 * in the page, by the same painter.js. It reads the API's figures (Plotly's format:
 * scatter or scatterpolar traces; see traces.js for what it takes) and keeps them on the
 * element as `div.data` and `div.layout` (with the ranges drawn) for its readers. Box
 * zoom by dragging on a cartesian plot, a double click to undo it; the zoom and the
 * legend's hidden curves stay while the figure's revision does. Exports draw the same
 * figure with Plotly (exports.js).
 */
import { el, setIf, replaceText } from "../base/dom.js";
import { markup } from "./text.js";
import { legendEntries, toggleKey } from "./traces.js";
import { Painter } from "./painter.js";

const ZOOM_MIN_PX = 6;       // a drag shorter than this either way is a click, not a zoom

// a marker's symbol in the legend, as a character
const GLYPHS = { circle: "●", square: "■", diamond: "◆", "triangle-up": "▲", "triangle-down": "▼", x: "✕", cross: "+",
                 "circle-open": "○", "square-open": "□", "diamond-open": "◇", "triangle-up-open": "△", "triangle-down-open": "▽" };
const glyph = (symbol) => GLYPHS[Array.isArray(symbol) ? symbol[0] : symbol] || "●";

/** A text placed at (x, y) of the plot, its style written only when it moved: a style
 * set to what it holds is still a change to the browser (style and layout again). */
function place(node, x, y) {
  setIf(node.style, "left", `${Math.round(x)}px`);
  setIf(node.style, "top", `${Math.round(y)}px`);
}

// the text each title, note and legend entry shows (as markup): rewritten only on a change
const shownText = new WeakMap();

/** Shows Plotly's markup `text` in `node`, rewriting only the text that changed in place
 * (a legend entry whose number moves with a slider: no new nodes to style and lay out). */
function setText(node, text) {
  if (shownText.get(node) === text) return;
  shownText.set(node, text);
  replaceText(node, markup(text));
  setIf(node, "hidden", !text);
}

/** The layout with the ranges its axes were drawn over (fitted to the data where it gave
 * none, or zoomed), as readers of `div.layout` find them after a Plotly draw. */
function drawnRanges(layout, ranges) {
  const out = { ...layout };
  if (ranges.r) out.polar = { ...layout.polar, radialaxis: { ...layout.polar?.radialaxis, range: ranges.r } };
  for (const k of ["x", "y", "y2"]) {
    const key = k === "y2" ? "yaxis2" : `${k}axis`;
    if (ranges[k]) out[key] = { ...layout[key], range: ranges[k] };
  }
  return out;
}

/** The painter of one canvas, asked by messages: in a worker of its own where the
 * browser can hand it the canvas (OffscreenCanvas), else here. ask(op, args) resolves
 * with its answer either way. */
class PainterPort {
  constructor(canvas) {
    if (typeof canvas.transferControlToOffscreen === "function" && typeof Worker === "function") {
      try {
        this.worker = new Worker(new URL("./worker.js", import.meta.url), { type: "module" });
        const offscreen = canvas.transferControlToOffscreen();
        this.waiting = new Map();
        this.seq = 0;
        this.worker.onmessage = ({ data: { id, result, error } }) => {
          const w = this.waiting.get(id);
          this.waiting.delete(id);
          if (error === undefined) w?.resolve(result);
          else w?.reject(new Error(error));
        };
        this.worker.onerror = (e) => {
          for (const w of this.waiting.values()) w.reject(new Error(`the chart's worker failed: ${e.message || "not loaded"}`));
          this.waiting.clear();
        };
        this.ask("init", { canvas: offscreen }, [offscreen]);
        return;
      } catch {
        this.worker?.terminate();        // no module workers here: painted in the page below
        this.worker = null;
      }
    }
    this.local = new Painter(canvas);
  }

  ask(op, args = {}, transfer = []) {
    if (this.local) {
      try {
        return Promise.resolve(this.local[op](args));
      } catch (e) {
        return Promise.reject(e);
      }
    }
    const id = ++this.seq;
    return new Promise((resolve, reject) => {
      this.waiting.set(id, { resolve, reject });
      this.worker.postMessage({ id, op, ...args }, transfer);
    });
  }

  close() { this.worker?.terminate(); }
}

export class Chart {
  constructor(div) {
    this.div = div;
    div.classList.add("chart");
    this.legend = el("div", { class: "chart-legend" });
    this.canvas = el("canvas", { class: "chart-canvas", role: "img" });
    this.titles = { x: el("div", { class: "chart-title chart-xtitle" }), y: el("div", { class: "chart-title chart-ytitle" }),
                    y2: el("div", { class: "chart-title chart-y2title" }) };
    this.notes = el("div", { class: "chart-notes" });
    this.tip = el("div", { class: "chart-tip", hidden: true, role: "tooltip" });
    this.box = el("div", { class: "chart-zoom", hidden: true });
    this.area = el("div", { class: "chart-area" }, this.canvas, ...Object.values(this.titles), this.notes, this.box, this.tip);
    div.replaceChildren(this.legend, this.area);
    this.port = new PainterPort(this.canvas);
    Object.assign(this, { figure: null, revision: null, hidden: new Set(), zoom: null, size: null, legendKey: null, plot: null });
    this.resize = new ResizeObserver(([e]) => {
      const { width, height } = e.contentRect;
      if (this.size && Math.abs(width - this.size.w) < 0.5 && Math.abs(height - this.size.h) < 0.5) return;
      this.size = { w: width, h: height };
      if (this.figure) this.paint();
    });
    this.resize.observe(this.area);
    this.area.addEventListener("pointermove", (e) => this.hover(e));
    this.area.addEventListener("pointerleave", () => { this.tip.hidden = true; });
    this.area.addEventListener("pointerdown", (e) => this.zoomStart(e));
    this.area.addEventListener("dblclick", () => { if (this.zoom) { this.zoom = null; this.paint(); } });
  }

  /** Draws `figure` ({data, layout}); resolves when it is on the canvas (with the
   * painter's answer, paintedAt: when, in ms since the epoch). revision: what
   * the zoom and the hidden curves belong to (a new one forgets them). */
  draw(figure, { revision = null } = {}) {
    if (revision !== this.revision) Object.assign(this, { revision, zoom: null, hidden: new Set() });
    this.figure = figure;
    this.div.data = figure.data;
    this.div.layout = figure.layout;
    return this.paint();
  }

  dispose() {
    this.resize.disconnect();
    this.port.close();
    this.div.replaceChildren();
    this.div.classList.remove("chart");
    delete this.div.data;
    delete this.div.layout;
    this.figure = null;
  }

  /** Paints the current figure (a newer call while one paints waits for it and paints
   * the figure current then: one paint in flight, the newest next). Resolves, when the
   * figure current at the call is on the canvas, with the painter's answer (painter.js). */
  paint() {
    if (this.painting) return (this.next ||= this.painting.then(() => { this.next = null; return this.paint(); }));
    const { data, layout = {} } = this.figure;
    this.showLegend(legendEntries({ data, layout }, this.hidden), layout);
    if (!this.size) {
      const r = this.area.getBoundingClientRect();
      this.size = { w: r.width, h: r.height };
    }
    const { w, h } = this.size;
    setIf(this.canvas.style, "width", `${w}px`);
    setIf(this.canvas.style, "height", `${h}px`);
    this.font ||= { tick: `12px ${getComputedStyle(this.div).fontFamily}`, color: "#444" };
    const ask = { figure: { data, layout }, w, h, dpr: window.devicePixelRatio || 1, hidden: [...this.hidden],
                  zoom: this.zoom, font: this.font };
    this.painting = this.port.ask("paint", ask).then((out) => {
      this.plot = out;
      this.div.layout = drawnRanges(layout, out.ranges);
      for (const k of ["x", "y", "y2"]) {
        const t = out.titles[k];
        setText(this.titles[k], t?.text || "");
        if (t?.text) place(this.titles[k], t.x, t.y);
      }
      if (out.area) this.showNotes(layout, out.area);       // none on a hidden (zero-size) plot
      setIf(this.tip, "hidden", true);
      return out;
    }).finally(() => { this.painting = null; });
    return this.painting;
  }

  /** The canvas's pixels as drawn ({width, height, data}: RGBA rows), for a reader that
   * checks what the chart shows. */
  pixels() { return this.port.ask("pixels"); }

  /** The legend: one entry per named curve (or group), its line's colour and dash; a
   * click hides or shows the curve (its whole group). Built again only when its entries'
   * kinds change; names that change (a number in one) are rewritten in place. */
  showLegend(named, layout) {
    const entries = layout.showlegend === false ? [] : named;
    const key = JSON.stringify(entries.map((tr) => [toggleKey(tr), tr.color, tr.dash, tr.lines, tr.markers && tr.marker.symbol, tr.hidden, tr.fill]));
    if (key === this.legendKey) {
      [...this.legend.children].forEach((item, k) => setText(item.lastChild, entries[k].name));
      return;
    }
    this.legendKey = key;
    this.legend.replaceChildren(...entries.map((tr) => {
      const swatch = tr.lines ? el("span", { class: "chart-swatch" })
        : el("span", { class: "chart-swatch-marker", text: glyph(tr.marker.symbol) });
      if (tr.lines) {
        swatch.style.borderTopColor = tr.color;
        swatch.style.borderTopStyle = tr.dash === "solid" ? "solid" : tr.dash === "dot" ? "dotted" : "dashed";
      } else swatch.style.color = tr.fill !== "none" ? tr.fillcolor : tr.marker.color;
      const text = el("span", { class: "chart-legend-text" });
      setText(text, tr.name);
      const item = el("button", { type: "button", class: `chart-legend-item${tr.hidden ? " off" : ""}`,
                                  title: tr.hidden ? "Show this curve" : "Hide this curve" }, swatch, text);
      item.addEventListener("click", () => {
        const k = toggleKey(tr);
        if (this.hidden.has(k)) this.hidden.delete(k); else this.hidden.add(k);
        this.paint();
      });
      return item;
    }));
    setIf(this.legend, "hidden", !entries.length);
  }

  /** The figure's notes placed on the paper (annotations with xref/yref "paper"). */
  showNotes(layout, area) {
    const notes = (layout.annotations || []).filter((a) => a.xref === "paper" && a.yref === "paper" && a.text);
    const key = JSON.stringify(notes);
    if (key !== this.notesKey) {
      this.notesKey = key;
      this.notes.replaceChildren(...notes.map((a) => el("span", { class: "chart-note", "data-name": a.name || "" }, markup(a.text))));
    }
    [...this.notes.children].forEach((n, k) => {
      const a = notes[k];
      place(n, area.x + (a.x ?? 0) * area.w, area.y + (1 - (a.y ?? 1)) * area.h);
      setIf(n.style, "transform", `translate(${a.xanchor === "right" ? "-100%" : a.xanchor === "center" ? "-50%" : "0"}, ${a.yanchor === "top" ? "0" : "-100%"})`);
    });
  }

  hover(e) {
    if (!this.plot?.area || this.dragging) return;
    const r = this.area.getBoundingClientRect();
    const at = { x: e.clientX - r.left, y: e.clientY - r.top };
    if (this.hovering) { this.hoverNext = at; return; }          // one question in flight, the newest next
    this.hovering = this.port.ask("hover", at).then((hit) => {
      if (!hit) { setIf(this.tip, "hidden", true); return; }
      this.tip.replaceChildren(...hit.lines.map((line) => el("div", {}, markup(line))));
      this.tip.style.borderColor = hit.color;
      this.tip.hidden = false;
      const left = hit.x + 12 + this.tip.offsetWidth > r.width ? hit.x - 12 - this.tip.offsetWidth : hit.x + 12;
      Object.assign(this.tip.style, { left: `${Math.max(0, left)}px`, top: `${Math.max(0, hit.y - this.tip.offsetHeight / 2)}px` });
    }).catch(() => {}).finally(() => {
      this.hovering = null;
      const next = this.hoverNext;
      this.hoverNext = null;
      if (next) this.hover({ clientX: next.x + r.left, clientY: next.y + r.top });
    });
  }

  /** A box zoom on a cartesian plot: the dragged rectangle becomes the axes' ranges. */
  zoomStart(e) {
    const a = this.plot?.area;
    if (!a || this.plot.polar || e.button !== 0) return;
    const r = this.area.getBoundingClientRect();
    const x0 = e.clientX - r.left, y0 = e.clientY - r.top;
    if (x0 < a.x || x0 > a.x + a.w || y0 < a.y || y0 > a.y + a.h) return;
    this.area.setPointerCapture(e.pointerId);
    this.dragging = true;
    this.tip.hidden = true;
    const clamp = (v, lo, hi) => Math.min(hi, Math.max(lo, v));
    const move = (ev) => {
      const x1 = clamp(ev.clientX - r.left, a.x, a.x + a.w), y1 = clamp(ev.clientY - r.top, a.y, a.y + a.h);
      Object.assign(this.box.style, { left: `${Math.min(x0, x1)}px`, top: `${Math.min(y0, y1)}px`,
                                      width: `${Math.abs(x1 - x0)}px`, height: `${Math.abs(y1 - y0)}px` });
      this.box.hidden = false;
      return [x1, y1];
    };
    const up = (ev) => {
      this.area.removeEventListener("pointermove", move);
      this.area.removeEventListener("pointerup", up);
      this.dragging = false;
      const [x1, y1] = move(ev);
      this.box.hidden = true;
      if (Math.abs(x1 - x0) < ZOOM_MIN_PX || Math.abs(y1 - y0) < ZOOM_MIN_PX) return;
      this.zooming = this.port.ask("zoom", { box: [x0, y0, x1, y1] }).then((ranges) => {
        if (!ranges) return null;
        this.zoom = ranges;
        return this.paint();
      }).finally(() => { this.zooming = null; });
    };
    this.area.addEventListener("pointermove", move);
    this.area.addEventListener("pointerup", up);
  }
}
