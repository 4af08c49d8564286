/* The chart's canvas side: it paints a figure on a canvas (an OffscreenCanvas in the
 * chart's worker, or the page's own canvas where there is no worker) and answers
 * questions about what it painted: the point under the pointer, the ranges of a zoom box,
 * the pixels. It touches no page element, so it runs in either place unchanged; every
 * request and answer is a plain object (worker.js passes them as messages).
 */
import { readTraces, toggleKey } from "./traces.js";
import { drawTraces } from "./marks.js";
import { drawCartesian } from "./cartesian.js";
import { drawPolar } from "./polar.js";
import { hoverText, nearest } from "./hover.js";

export class Painter {
  constructor(canvas) {
    this.canvas = canvas;
    this.frame = null;
  }

  /** {figure, w, h, dpr, hidden: [toggle keys], zoom, font} → what the page shows beside the
   * canvas: the plot area, the axes' titles and where, the ranges drawn, and when the
   * canvas was painted (paintedAt). */
  paint({ figure, w, h, dpr, hidden = [], zoom = null, font }) {
    const layout = figure.layout || {};
    const traces = readTraces({ data: figure.data, layout });
    const off = new Set(hidden);
    for (const tr of traces) if (off.has(toggleKey(tr))) tr.hidden = true;
    const width = Math.round(w * dpr), height = Math.round(h * dpr);
    if (this.canvas.width !== width || this.canvas.height !== height) Object.assign(this.canvas, { width, height });
    const ctx = this.canvas.getContext("2d");
    ctx.setTransform(dpr, 0, 0, dpr, 0, 0);
    ctx.clearRect(0, 0, w, h);
    this.frame = null;
    if (w < 20 || h < 20) return { area: null, titles: {}, ranges: {} };
    const polar = traces.some((tr) => tr.polar);
    const drawn = zoom && !polar ? { ...layout, xaxis: { ...layout.xaxis, range: zoom.x }, yaxis: { ...layout.yaxis, range: zoom.y } } : layout;
    const frame = (polar ? drawPolar : drawCartesian)(ctx, drawn, traces, w, h, font);
    ctx.save();
    if (frame.clip) frame.clip();
    else { ctx.beginPath(); ctx.rect(frame.area.x, frame.area.y, frame.area.w, frame.area.h); ctx.clip(); }
    drawTraces(ctx, traces, frame.at, { zeroY: frame.zeroY, atY: frame.atY });
    ctx.restore();
    this.frame = { ...frame, traces, polar, pts: null };
    // when the pixels were done, on the clock every thread of the page shares (ms since
    // the epoch): the page learns of it a task later, after whatever it was doing
    return { area: frame.area, titles: frame.titles, ranges: frame.ranges, polar,
             paintedAt: performance.timeOrigin + performance.now() };
  }

  /** The nearest hovered point to (x, y): {lines, color, x, y}, or null. */
  hover({ x, y }) {
    const f = this.frame;
    if (!f) return null;
    f.pts ||= f.traces.map((tr) => (tr.hover && !tr.hidden ? Array.from(tr.y, (_, i) => f.at(tr)(i)) : null));
    const hit = nearest(f.traces, f.pts, x, y);
    if (!hit) return null;
    return { lines: hoverText(hit.tr, hit.i).split(/<br\s*\/?>/i), color: hit.tr.color, x: hit.p[0], y: hit.p[1] };
  }

  /** The axes' ranges (decades on a log axis) of a box [x0, y0, x1, y1] in pixels. */
  zoom({ box: [x0, y0, x1, y1] }) {
    const f = this.frame;
    if (!f || f.polar) return null;
    const unit = (s, p) => (s.log ? Math.log10(s.value(p)) : s.value(p));
    return { x: [unit(f.x, Math.min(x0, x1)), unit(f.x, Math.max(x0, x1))],
             y: [unit(f.y, Math.max(y0, y1)), unit(f.y, Math.min(y0, y1))] };
  }

  /** The canvas's pixels as drawn: {width, height, data} (RGBA). */
  pixels() {
    const { width, height } = this.canvas;
    if (!width || !height) return { width, height, data: new Uint8ClampedArray(0) };
    const img = this.canvas.getContext("2d").getImageData(0, 0, width, height);
    return { width, height, data: img.data };
  }
}
