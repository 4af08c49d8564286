/* A cartesian plot: x, y and an optional second y axis on the right (Plotly's yaxis2,
 * overlaying y). Ranges as the figure gives them, else fitted to the data (with 5 %
 * room, from zero where the axis says rangemode "tozero"). Draws the grid, the axes and
 * their tick labels; the curves are drawn through the map it returns.
 */
import { Scale } from "./scale.js";

const TICK = 5, PAD = 6, TITLE = 18;     // px: tick length, label gap, an axis title's line
const X_SPACING = 80, Y_SPACING = 44;    // px between labelled ticks, about

/** [lo, hi] of the values (decades on a log axis) the traces put on an axis. */
function dataRange(traces, pick, log, axis) {
  let lo = Infinity, hi = -Infinity;
  for (const tr of traces) {
    if (tr.hidden) continue;
    const vs = pick(tr);
    if (!vs) continue;
    const err = axis !== "x" && tr.error ? tr.error.array : null;
    for (let i = 0; i < vs.length; i++) {
      const v = vs[i], d = err ? err[i] || 0 : 0;
      for (const w of d ? [v - d, v + d] : [v]) {
        if (!Number.isFinite(w) || (log && w <= 0)) continue;
        const u = log ? Math.log10(w) : w;
        if (u < lo) lo = u;
        if (u > hi) hi = u;
      }
    }
  }
  return lo <= hi ? [lo, hi] : null;
}

/** The range an axis is drawn over. */
export function axisRange(axis, traces, pick, name) {
  if (Array.isArray(axis.range) && axis.range.every(Number.isFinite) && axis.range[0] !== axis.range[1]) return axis.range;
  const log = axis.type === "log";
  let r = dataRange(traces, pick, log, name) || [0, 1];      // nothing to show: 0-1 (1-10 on a log axis)
  if (!log && axis.rangemode === "tozero") r = [Math.min(0, r[0]), Math.max(0, r[1])];
  const span = r[1] - r[0] || Math.abs(r[0]) || 1;
  const pad = name === "x" ? 0 : 0.05 * span;
  return [r[0] - (axis.rangemode === "tozero" && r[0] === 0 ? 0 : pad), r[1] + pad];
}

/** Lays out and draws the frame on `ctx` (w × h CSS pixels); returns the plot area,
 * the scales and at(tr): index → pixel or null. */
export function drawCartesian(ctx, layout, traces, w, h, font) {
  const xa = layout.xaxis || {}, ya = layout.yaxis || {};
  const two = traces.some((tr) => tr.axis === "y2");
  const y2a = two ? layout.yaxis2 || {} : null;
  const ranges = {
    x: axisRange(xa, traces, (tr) => tr.x, "x"),
    y: axisRange(ya, traces.filter((tr) => tr.axis === "y"), (tr) => tr.y, "y"),
    y2: two ? axisRange(y2a, traces.filter((tr) => tr.axis === "y2"), (tr) => tr.y, "y2") : null,
  };
  ctx.font = font.tick;
  const top = 10, bottom = TICK + PAD + 12 + (xa.title?.text ? TITLE + 4 : 4);
  const ph = Math.max(10, h - top - bottom);
  const y = new Scale({ ...ya, range: ranges.y }, [top + ph, top]);
  const yTicks = y.ticks(ph, Y_SPACING);
  const labelW = (ticks) => Math.max(0, ...ticks.map((t) => ctx.measureText(t.label).width));
  const y2 = two ? new Scale({ ...y2a, range: ranges.y2 }, [top + ph, top]) : null;
  const y2Ticks = two ? y2.ticks(ph, Y_SPACING) : [];
  const left = Math.ceil(TICK + PAD + labelW(yTicks) + (ya.title?.text ? TITLE + 6 : 4));
  const right = two ? Math.ceil(TICK + PAD + labelW(y2Ticks) + (y2a.title?.text ? TITLE + 6 : 4)) : 18;
  const pw = Math.max(10, w - left - right);
  const area = { x: left, y: top, w: pw, h: ph };
  const x = new Scale({ ...xa, range: ranges.x }, [left, left + pw]);
  const xTicks = x.ticks(pw, X_SPACING);

  // grid
  ctx.lineWidth = 1;
  ctx.strokeStyle = xa.gridcolor || "#e5e5e5";
  ctx.beginPath();
  if (xa.showgrid !== false) for (const t of xTicks) { const p = Math.round(x.px(t.v)) + 0.5; ctx.moveTo(p, top); ctx.lineTo(p, top + ph); }
  if (ya.showgrid !== false) for (const t of yTicks) { const p = Math.round(y.px(t.v)) + 0.5; ctx.moveTo(left, p); ctx.lineTo(left + pw, p); }
  ctx.stroke();
  if (two && y2a.zeroline && !y2.log && ranges.y2[0] < 0 && ranges.y2[1] > 0) {
    ctx.strokeStyle = y2a.zerolinecolor || "#bbb";
    ctx.beginPath();
    const p = Math.round(y2.px(0)) + 0.5;
    ctx.moveTo(left, p); ctx.lineTo(left + pw, p);
    ctx.stroke();
  }
  // axes: lines, ticks and labels
  ctx.strokeStyle = xa.linecolor || "#888";
  ctx.fillStyle = font.color;
  ctx.beginPath();
  ctx.moveTo(left, top + ph + 0.5); ctx.lineTo(left + pw, top + ph + 0.5);
  ctx.moveTo(left - 0.5, top); ctx.lineTo(left - 0.5, top + ph);
  if (two) { ctx.moveTo(left + pw + 0.5, top); ctx.lineTo(left + pw + 0.5, top + ph); }
  for (const t of xTicks) { const p = Math.round(x.px(t.v)) + 0.5; ctx.moveTo(p, top + ph); ctx.lineTo(p, top + ph + TICK); }
  for (const t of yTicks) { const p = Math.round(y.px(t.v)) + 0.5; ctx.moveTo(left, p); ctx.lineTo(left - TICK, p); }
  for (const t of y2Ticks) { const p = Math.round(y2.px(t.v)) + 0.5; ctx.moveTo(left + pw, p); ctx.lineTo(left + pw + TICK, p); }
  ctx.stroke();
  ctx.textAlign = "center";
  ctx.textBaseline = "top";
  for (const t of xTicks) ctx.fillText(t.label, x.px(t.v), top + ph + TICK + 2);
  ctx.textBaseline = "middle";
  ctx.textAlign = "right";
  for (const t of yTicks) ctx.fillText(t.label, left - TICK - 3, y.px(t.v));
  ctx.textAlign = "left";
  for (const t of y2Ticks) ctx.fillText(t.label, left + pw + TICK + 3, y2.px(t.v));

  const scaleOf = (tr) => (tr.axis === "y2" ? y2 : y);
  const at = (tr) => {
    const ys = scaleOf(tr);
    return (i) => {
      const px = x.px(tr.x[i]), py = ys.px(tr.y[i]);
      return Number.isFinite(px) && Number.isFinite(py) ? [px, py] : null;
    };
  };
  const titles = {
    x: { text: xa.title?.text || "", x: left + pw / 2, y: h - 4 },
    y: { text: ya.title?.text || "", x: 4, y: top + ph / 2 },
    y2: two ? { text: y2a.title?.text || "", x: w - 4, y: top + ph / 2 } : null,
  };
  return { area, at, titles, ranges, x, y, y2,
           zeroY: (tr) => { const s = scaleOf(tr); return s.log ? top + ph : Math.min(top + ph, Math.max(top, s.px(0))); },
           atY: (tr) => (i, v) => scaleOf(tr).px(v) };
}
