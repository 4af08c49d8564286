/* The held canvases' drawing, in a worker (heldcanvas.js posts what to draw).
 *
 * Each plot's overlay canvas hands its OffscreenCanvas here once; then every held frame
 * posts the placed traces (points as flat Float32Arrays, styles as Plotly left them on
 * its elements, the clip as a rect or an SVG path), and the canvas is cleared and drawn
 * here: the page's main thread, which handles the slider, neither issues the 2-D calls
 * nor finalises and pushes the canvas's frames.
 *
 * Messages: {id, canvas} (the surface, once); {id, size: [w, h]} (device pixels; sizing
 * clears); {id, clear: true}; {id, scale, traces} (clear, then draw); {id, read} (answers
 * {read, pixels}: what the canvas shows, for the tests).
 */
const surfaces = new Map();

const px = (v) => Number.parseFloat(v) || 0;
const alpha = (...vs) => vs.reduce((a, v) => a * (v === "" || v === undefined ? 1 : Number(v)), 1);
const dashes = (v) => (!v || v === "none" ? [] : v.split(/[\s,]+/).map(px));

function stroke(ctx, style) {
  ctx.strokeStyle = style.stroke;
  ctx.lineWidth = px(style.strokeWidth);
  ctx.globalAlpha = alpha(style.strokeOpacity, style.opacity);
  ctx.setLineDash(dashes(style.strokeDasharray));
}

/** One run's points (x0, y0, x1, y1, …) as a subpath. */
function trace(ctx, pts) {
  ctx.moveTo(pts[0], pts[1]);
  for (let i = 2; i < pts.length; i += 2) ctx.lineTo(pts[i], pts[i + 1]);
}

function clipPath({ rect, d, at }) {
  const path = new Path2D();
  if (rect) path.rect(...rect);
  else path.addPath(new Path2D(d), new DOMMatrix().translate(at[0], at[1]));
  return path;
}

function drawTrace(ctx, { fill, runs, lines, bars, half, marks }) {
  if (fill) {
    ctx.fillStyle = fill.fill;
    ctx.globalAlpha = alpha(fill.fillOpacity, fill.opacity);
    ctx.beginPath();
    for (const run of runs) {
      trace(ctx, run);
      ctx.closePath();
    }
    ctx.fill();
  }
  // error bars and markers each in their own element's style, as the SVG writer leaves
  // them (Plotly may style them point by point)
  for (const { style, x, hi, lo } of bars) {
    stroke(ctx, style);
    ctx.beginPath();
    ctx.moveTo(x - half, hi); ctx.lineTo(x + half, hi);
    ctx.moveTo(x, hi); ctx.lineTo(x, lo);
    ctx.moveTo(x - half, lo); ctx.lineTo(x + half, lo);
    ctx.stroke();
  }
  runs.forEach((run, k) => {
    const style = lines[k];
    if (!(px(style.strokeWidth) > 0)) return;
    stroke(ctx, style);
    ctx.beginPath();
    trace(ctx, run);
    ctx.stroke();
  });
  const shapes = new Map();        // a marker's outline by its path (one symbol and size: one)
  for (const { d, style, x, y } of marks) {
    if (!shapes.has(d)) shapes.set(d, new Path2D(d));
    ctx.fillStyle = style.fill;
    ctx.globalAlpha = alpha(style.fillOpacity, style.opacity);
    ctx.translate(x, y);
    ctx.fill(shapes.get(d));
    if (px(style.strokeWidth) > 0) {
      stroke(ctx, style);
      ctx.setLineDash([]);
      ctx.stroke(shapes.get(d));
    }
    ctx.translate(-x, -y);
  }
}

self.onmessage = ({ data: m }) => {
  if (m.canvas) surfaces.set(m.id, m.canvas);
  const surface = surfaces.get(m.id);
  if (!surface) return;
  if (m.size) [surface.width, surface.height] = m.size;
  const ctx = surface.getContext("2d");
  if (m.clear || m.traces) {
    ctx.setTransform(1, 0, 0, 1, 0, 0);
    ctx.clearRect(0, 0, surface.width, surface.height);
  }
  for (const t of m.traces || []) {
    ctx.save();
    ctx.setTransform(m.scale, 0, 0, m.scale, 0, 0);
    if (t.clip) ctx.clip(clipPath(t.clip));
    ctx.translate(t.at[0], t.at[1]);
    drawTrace(ctx, t);
    ctx.restore();
  }
  if (m.read) self.postMessage({ read: m.read, pixels: ctx.getImageData(0, 0, surface.width, surface.height) });
};
