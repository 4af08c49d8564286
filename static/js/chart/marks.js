/* What a trace leaves on the canvas: its fill, line, error bars and markers, through a
 * map from a point's index to its pixel ([x, y], or null where it has none: a gap).
 */

// Plotly's dash names, in line widths
const DASHES = { solid: [], dot: [1, 2], dash: [4, 3], longdash: [8, 3], dashdot: [4, 2, 1, 2], longdashdot: [8, 2, 1, 2] };

export function dashOf(dash, width) {
  const w = Math.max(1, width);
  return (DASHES[dash] || DASHES.dash).map((d) => d * w);
}

/** Runs of consecutive points that have a pixel. */
function runs(n, at) {
  const out = [];
  let run = [];
  for (let i = 0; i < n; i++) {
    const p = at(i);
    if (p) run.push(p);
    else if (run.length) { out.push(run); run = []; }
  }
  if (run.length) out.push(run);
  return out;
}

function path(ctx, pts) {
  ctx.moveTo(pts[0][0], pts[0][1]);
  for (let k = 1; k < pts.length; k++) ctx.lineTo(pts[k][0], pts[k][1]);
}

/** Fill "toself" (the polygon of the points), "tozeroy" (down to `zeroY`) or "tonexty"
 * (down to the trace below, `below(i)` its pixel). */
export function drawFill(ctx, tr, at, { zeroY, below }) {
  if (tr.fill === "none") return;
  const n = tr.y.length;
  ctx.fillStyle = tr.fillcolor;
  ctx.beginPath();
  for (const run of runs(n, at)) {
    if (tr.fill === "toself") {
      path(ctx, run);
      ctx.closePath();
    } else {
      const idx = [];
      for (let i = 0; i < n; i++) if (at(i)) idx.push(i);
      path(ctx, run);
      const back = tr.fill === "tonexty" && below ? idx.map(below).filter(Boolean).reverse()
        : [[run[run.length - 1][0], zeroY], [run[0][0], zeroY]];
      for (const p of back) ctx.lineTo(p[0], p[1]);
      ctx.closePath();
      break;
    }
  }
  ctx.fill();
}

export function drawLine(ctx, tr, at) {
  ctx.strokeStyle = tr.color;
  ctx.lineWidth = tr.width;
  ctx.lineJoin = "round";
  ctx.setLineDash(tr.dash === "solid" ? [] : dashOf(tr.dash, tr.width));
  ctx.beginPath();
  for (const run of runs(tr.y.length, at)) path(ctx, run);
  ctx.stroke();
  ctx.setLineDash([]);
}

/** Vertical error bars of ± the trace's error array, with caps. `atY(i, v)`: the pixel
 * of value v at point i. */
export function drawErrors(ctx, tr, at, atY) {
  const e = tr.error;
  ctx.strokeStyle = e.color;
  ctx.lineWidth = e.thickness;
  ctx.beginPath();
  for (let i = 0; i < tr.y.length; i++) {
    const p = at(i), d = e.array[i];
    if (!p || !(d > 0)) continue;
    const top = atY(i, tr.y[i] + d), bottom = atY(i, tr.y[i] - d);
    const y0 = Number.isFinite(bottom) ? bottom : p[1], y1 = Number.isFinite(top) ? top : p[1];
    ctx.moveTo(p[0], y0); ctx.lineTo(p[0], y1);
    ctx.moveTo(p[0] - e.width, y0); ctx.lineTo(p[0] + e.width, y0);
    ctx.moveTo(p[0] - e.width, y1); ctx.lineTo(p[0] + e.width, y1);
  }
  ctx.stroke();
}

/** One marker's outline at (x, y), radius r: Plotly's symbol names, "-open" drawn
 * unfilled. */
function symbolPath(ctx, symbol, x, y, r) {
  const base = String(symbol).replace(/-open$/, "");
  if (base === "square") ctx.rect(x - r, y - r, 2 * r, 2 * r);
  else if (base === "diamond") { ctx.moveTo(x, y - r * 1.3); ctx.lineTo(x + r * 1.3, y); ctx.lineTo(x, y + r * 1.3); ctx.lineTo(x - r * 1.3, y); ctx.closePath(); }
  else if (base === "triangle-up") { ctx.moveTo(x, y - r * 1.2); ctx.lineTo(x + r * 1.1, y + r * 0.7); ctx.lineTo(x - r * 1.1, y + r * 0.7); ctx.closePath(); }
  else if (base === "triangle-down") { ctx.moveTo(x, y + r * 1.2); ctx.lineTo(x + r * 1.1, y - r * 0.7); ctx.lineTo(x - r * 1.1, y - r * 0.7); ctx.closePath(); }
  else if (base === "x") { const d = r * 0.9; ctx.moveTo(x - d, y - d); ctx.lineTo(x + d, y + d); ctx.moveTo(x - d, y + d); ctx.lineTo(x + d, y - d); }
  else if (base === "cross") { ctx.moveTo(x - r, y); ctx.lineTo(x + r, y); ctx.moveTo(x, y - r); ctx.lineTo(x, y + r);
  } else { ctx.moveTo(x + r, y); ctx.arc(x, y, r, 0, 2 * Math.PI); }
}

export function drawMarkers(ctx, tr, at) {
  const { size, symbol, color } = tr.marker;
  const r = size / 2;
  const symbols = Array.isArray(symbol) ? symbol : null;
  const colors = Array.isArray(color) ? color : null;
  ctx.lineWidth = 1.5;
  for (let i = 0; i < tr.y.length; i++) {
    const p = at(i);
    if (!p) continue;
    const sym = symbols ? symbols[i] : symbol, c = colors ? colors[i] : color;
    const open = /-open$/.test(sym) || sym === "x" || sym === "cross";
    ctx.beginPath();
    symbolPath(ctx, sym, p[0], p[1], r);
    if (open) { ctx.strokeStyle = c; ctx.stroke(); } else { ctx.fillStyle = c; ctx.fill(); }
  }
}

/** Every mark of the traces, fills first (under every line), through at(tr)(i). */
export function drawTraces(ctx, traces, atOf, { zeroY = () => 0, atY = null } = {}) {
  const shown = traces.filter((tr) => !tr.hidden);
  const byIndex = new Map(shown.map((tr) => [tr.index, tr]));
  for (const tr of shown) {
    if (tr.fill === "none") continue;
    const prev = tr.fill === "tonexty" ? previousOf(tr, traces, byIndex) : null;
    drawFill(ctx, tr, atOf(tr), { zeroY: zeroY(tr), below: prev ? atOf(prev) : null });
  }
  for (const tr of shown) {
    if (tr.lines) drawLine(ctx, tr, atOf(tr));
    if (tr.error && atY) drawErrors(ctx, tr, atOf(tr), atY(tr));
    if (tr.markers) drawMarkers(ctx, tr, atOf(tr));
  }
}

/** The trace a "tonexty" fill goes down to: the one before it in its stack group (or,
 * unstacked, the one before it); none: down to zero. */
function previousOf(tr, traces, shown) {
  for (let k = tr.index - 1; k >= 0; k--) {
    const o = traces[k];
    if (o.polar !== tr.polar || o.axis !== tr.axis) continue;
    if (tr.stack ? o.stack === tr.stack : true) return shown.has(o.index) ? o : (tr.stack ? o : null);
  }
  return null;
}
