/* A small canvas chart for the curve panels: one draw(figure) that paints the whole
 * figure in one go (axes, grid, curves) on a canvas, with its legend, axis titles and
 * notes as page text. Built for data that moves with a slider (uPlot's idea): drawing a
 * figure again costs a millisecond or two whatever changed, so there is one way to draw
 * and nothing to keep in step. It reads the API's figures (Plotly's format: scatter or
 * scatterpolar traces; see traces.js for what it takes) and keeps them on the element
 * as `div.data` and `div.layout` for its readers. Box zoom by dragging on a cartesian
 * plot, a double click to undo it; the zoom and the legend's hidden curves stay while
 * the figure's revision does. Exports draw the same figure with Plotly (exports.js).
 */
import { el } from "../base/dom.js";
import { markup } from "./text.js";
import { readTraces } from "./traces.js";
import { drawTraces } from "./marks.js";
import { drawCartesian } from "./cartesian.js";
import { drawPolar } from "./polar.js";
import { hoverText, nearest } from "./hover.js";

const ZOOM_MIN_PX = 6;       // a drag shorter than this either way is a click, not a zoom

// a marker's symbol in the legend, as a character
const GLYPHS = { circle: "●", square: "■", diamond: "◆", "triangle-up": "▲", "triangle-down": "▼", x: "✕", cross: "+",
                 "circle-open": "○", "square-open": "□", "diamond-open": "◇", "triangle-up-open": "△", "triangle-down-open": "▽" };
const glyph = (symbol) => GLYPHS[Array.isArray(symbol) ? symbol[0] : symbol] || "●";

/** Plotly's title text of an axis or figure, or "". */
const textOf = (t) => String((typeof t === "string" ? t : t?.text) || "");

function setText(node, text) {
  if (node.dataset.text === text) return;
  node.dataset.text = text;
  node.replaceChildren(markup(text));
  node.hidden = !text;
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
    Object.assign(this, { figure: null, revision: null, hidden: new Set(), zoom: null, size: null, legendKey: null, frame: null });
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

  /** Draws `figure` ({data, layout}) now. revision: what the zoom and the hidden curves
   * belong to (a new one forgets them). */
  draw(figure, { revision = null } = {}) {
    if (revision !== this.revision) Object.assign(this, { revision, zoom: null, hidden: new Set() });
    this.figure = figure;
    this.div.data = figure.data;
    this.div.layout = figure.layout;
    this.paint();
  }

  dispose() {
    this.resize.disconnect();
    this.div.replaceChildren();
    this.div.classList.remove("chart");
    delete this.div.data;
    delete this.div.layout;
    this.figure = null;
  }

  paint() {
    const { data, layout = {} } = this.figure;
    const traces = readTraces({ data, layout });
    for (const tr of traces) if (this.hidden.has(tr.group ?? tr.name)) tr.hidden = true;
    this.showLegend(traces, layout);
    if (!this.size) {
      const r = this.area.getBoundingClientRect();
      this.size = { w: r.width, h: r.height };
    }
    const { w, h } = this.size;
    const dpr = window.devicePixelRatio || 1;
    if (this.canvas.width !== Math.round(w * dpr) || this.canvas.height !== Math.round(h * dpr)) {
      this.canvas.width = Math.round(w * dpr);
      this.canvas.height = Math.round(h * dpr);
      this.canvas.style.width = `${w}px`;
      this.canvas.style.height = `${h}px`;
    }
    const ctx = this.canvas.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, w, h);
    if (w < 20 || h < 20) return;
    const font = this.font ||= (() => {
      const cs = getComputedStyle(this.div);
      return { tick: `12px ${cs.fontFamily}`, color: "#444" };
    })();
    const polar = traces.some((tr) => tr.polar);
    const zoomed = this.zoom && !polar ? { ...layout, xaxis: { ...layout.xaxis, range: this.zoom.x }, yaxis: { ...layout.yaxis, range: this.zoom.y } } : layout;
    const frame = (polar ? drawPolar : drawCartesian)(ctx, zoomed, traces, w, h, font);
    ctx.save();
    if (frame.clip) frame.clip();
    else { ctx.beginPath(); ctx.rect(frame.area.x, frame.area.y, frame.area.w, frame.area.h); ctx.clip(); }
    drawTraces(ctx, traces, frame.at, { zeroY: frame.zeroY, atY: frame.atY });
    ctx.restore();
    this.frame = { ...frame, traces, polar };
    this.div.layout = drawnRanges(layout, frame.ranges);
    this.pts = null;                                   // the hovered points, found when asked
    for (const k of ["x", "y", "y2"]) {
      const t = frame.titles[k];
      setText(this.titles[k], t?.text || "");
      if (t?.text) Object.assign(this.titles[k].style, { left: `${t.x}px`, top: `${t.y}px` });
    }
    this.showNotes(layout, frame.area);
    this.tip.hidden = true;
  }

  /** The legend: one entry per named curve (or group), its line's colour and dash; a
   * click hides or shows the curve (its whole group). Rebuilt only when it changes. */
  showLegend(traces, layout) {
    const entries = layout.showlegend === false ? [] : traces.filter((tr) => tr.legend);
    const key = JSON.stringify(entries.map((tr) => [tr.name, tr.color, tr.dash, tr.lines, tr.markers && tr.marker.symbol, tr.hidden, tr.fill]));
    if (key === this.legendKey) return;
    this.legendKey = key;
    this.legend.replaceChildren(...entries.map((tr) => {
      const swatch = tr.lines ? el("span", { class: "chart-swatch" })
        : el("span", { class: "chart-swatch-marker", text: glyph(tr.marker.symbol) });
      if (tr.lines) {
        swatch.style.borderTopColor = tr.color;
        swatch.style.borderTopStyle = tr.dash === "solid" ? "solid" : tr.dash === "dot" ? "dotted" : "dashed";
      } else swatch.style.color = tr.fill !== "none" ? tr.fillcolor : tr.marker.color;
      const item = el("button", { type: "button", class: `chart-legend-item${tr.hidden ? " off" : ""}`,
                                  title: tr.hidden ? "Show this curve" : "Hide this curve" }, swatch, el("span", { class: "chart-legend-text" }, markup(tr.name)));
      item.addEventListener("click", () => {
        const k = tr.group ?? tr.name;
        if (this.hidden.has(k)) this.hidden.delete(k); else this.hidden.add(k);
        this.paint();
      });
      return item;
    }));
    this.legend.hidden = !entries.length;
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
      Object.assign(n.style, { left: `${area.x + (a.x ?? 0) * area.w}px`, top: `${area.y + (1 - (a.y ?? 1)) * area.h}px`,
                               transform: `translate(${a.xanchor === "right" ? "-100%" : a.xanchor === "center" ? "-50%" : "0"}, ${a.yanchor === "top" ? "0" : "-100%"})` });
    });
  }

  hover(e) {
    if (!this.frame || this.dragging) return;
    const r = this.area.getBoundingClientRect();
    const px = e.clientX - r.left, py = e.clientY - r.top;
    const { traces, at } = this.frame;
    this.pts ||= traces.map((tr) => (tr.hover && !tr.hidden ? Array.from(tr.y, (_, i) => at(tr)(i)) : null));
    const hit = nearest(traces, this.pts, px, py);
    if (!hit) { this.tip.hidden = true; return; }
    this.tip.replaceChildren(...hoverText(hit.tr, hit.i).split(/<br\s*\/?>/i).map((line) => el("div", {}, markup(line))));
    this.tip.style.borderColor = hit.tr.color;
    this.tip.hidden = false;
    const left = hit.p[0] + 12 + this.tip.offsetWidth > r.width ? hit.p[0] - 12 - this.tip.offsetWidth : hit.p[0] + 12;
    Object.assign(this.tip.style, { left: `${Math.max(0, left)}px`, top: `${Math.max(0, hit.p[1] - this.tip.offsetHeight / 2)}px` });
  }

  /** A box zoom on a cartesian plot: the dragged rectangle becomes the axes' ranges. */
  zoomStart(e) {
    if (!this.frame || this.frame.polar || e.button !== 0) return;
    const r = this.area.getBoundingClientRect(), a = this.frame.area;
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
      this.box.hidden = true;
      const [x1, y1] = move(ev);
      this.box.hidden = true;
      if (Math.abs(x1 - x0) < ZOOM_MIN_PX || Math.abs(y1 - y0) < ZOOM_MIN_PX) return;
      const { x, y } = this.frame;
      const unit = (s, p) => (s.log ? Math.log10(s.value(p)) : s.value(p));
      this.zoom = { x: [unit(x, Math.min(x0, x1)), unit(x, Math.max(x0, x1))], y: [unit(y, Math.max(y0, y1)), unit(y, Math.min(y0, y1))] };
      this.paint();
    };
    this.area.addEventListener("pointermove", move);
    this.area.addEventListener("pointerup", up);
  }
}
