/* While a slider is held, the curves drawn on a canvas laid over the plot.
 *
 * Writing a trace's SVG paths (svgpaths.js) costs the page's main thread the path
 * strings, then Blink's style, layout, paint and layerisation of the changed paths: a
 * frame that redrew four panels took 7-10 ms, one that only moved the slider 3-4 ms
 * (BENCHMARKS.md §5), and the slider's input events waited behind it. On a canvas the
 * same points are a few hundred lineTo calls and the SVG underneath is not touched; the
 * canvas draws on its OffscreenCanvas, whose frames go to the compositor without the
 * page's paint and commit. The points are the ones svgpaths.js would write (its
 * geometry()), in the styles read from the elements Plotly drew, clipped as Plotly
 * clips them; on release the SVG is written again and the canvas cleared (endHeld).
 *
 * The canvas stays over the plot, blank when no slider is held, made while the page is
 * idle (readyHeld); the plot's SVG traces are hidden while it shows the curves (the
 * class HELD on the plot div, style.css). What the canvas cannot place as the SVG would
 * (a transform other than a translation, a clip it cannot read) leaves drawHeld false,
 * and the caller writes the SVG.
 */
import { geometry } from "./svgpaths.js";

const HELD = "held-canvas";

/** An element's own translation ([0, 0] without a transform), or null if its
 * transform is another one. */
function translation(node) {
  const t = node.getAttribute?.("transform");
  if (!t) return [0, 0];
  const m = /^\s*translate\(\s*(-?[\d.e+-]+)[\s,]+(-?[\d.e+-]+)\s*\)\s*$/.exec(t);
  return m ? [Number(m[1]), Number(m[2])] : null;
}

/** The sum of the translations from `node` up to its <svg>, or null if one of them is
 * another transform. */
function offset(node) {
  let x = 0, y = 0;
  for (let n = node; n && n.tagName !== "svg"; n = n.parentNode) {
    const t = translation(n);
    if (!t) return null;
    x += t[0];
    y += t[1];
  }
  return [x, y];
}

/** The clip of a trace group as a Path2D in the SVG's pixels (its nearest clip-path:
 * a rect or a path), undefined when it has none, null when it cannot be read. */
function clipOf(group) {
  const owner = group.closest("[clip-path]");
  if (!owner || !group.ownerSVGElement?.contains(owner)) return undefined;
  const id = /url\(["']?#([^"')]+)["']?\)/.exec(owner.getAttribute("clip-path"))?.[1];
  const shape = id && document.getElementById(id)?.firstElementChild;
  const at = offset(owner), own = shape && translation(shape);
  if (!shape || !at || !own) return null;
  at[0] += own[0];
  at[1] += own[1];
  const path = new Path2D();
  if (shape.tagName === "rect") {
    const n = (a) => Number(shape.getAttribute(a) || 0);
    path.rect(at[0] + n("x"), at[1] + n("y"), n("width"), n("height"));
  } else if (shape.tagName === "path") {
    path.addPath(new Path2D(shape.getAttribute("d") || ""), new DOMMatrix().translate(at[0], at[1]));
  } else return null;
  return path;
}

const px = (v) => Number.parseFloat(v) || 0;
const alpha = (...vs) => vs.reduce((a, v) => a * (v === "" || v === undefined ? 1 : Number(v)), 1);
const dashes = (v) => (!v || v === "none" ? [] : v.split(/[\s,]+/).map(px));

/** What a plot div's overlay canvas (made once) is drawn on, sized to its SVG: the
 * canvas's OffscreenCanvas where the browser can hand one over (its frames then go to
 * the compositor directly, not through the page's paint and commit), else the canvas. */
function canvasOf(gd, svg) {
  let cv = gd.querySelector(`canvas.${HELD}-layer`);
  if (!cv) {
    cv = document.createElement("canvas");
    cv.className = `${HELD}-layer`;
    svg.after(cv);
    cv.surface = cv.transferControlToOffscreen ? cv.transferControlToOffscreen() : cv;
  }
  const s = cv.surface, w = px(svg.getAttribute("width")), h = px(svg.getAttribute("height")), r = window.devicePixelRatio || 1;
  if (s.width !== Math.round(w * r) || s.height !== Math.round(h * r)) {
    s.width = Math.round(w * r);
    s.height = Math.round(h * r);
    cv.style.width = `${w}px`;
    cv.style.height = `${h}px`;
  }
  return s;
}

function stroke(ctx, style) {
  ctx.strokeStyle = style.stroke;
  ctx.lineWidth = px(style.strokeWidth);
  ctx.globalAlpha = alpha(style.strokeOpacity, style.opacity);
  ctx.setLineDash(dashes(style.strokeDasharray));
}

function drawTrace(ctx, { lines, fill, marks, bars, half, segs, drawn, ticks }) {
  if (fill) {
    ctx.fillStyle = fill.style.fill;
    ctx.globalAlpha = alpha(fill.style.fillOpacity, fill.style.opacity);
    ctx.beginPath();
    for (const run of segs) {
      ctx.moveTo(run[0][0], run[0][1]);
      for (let i = 1; i < run.length; i++) ctx.lineTo(run[i][0], run[i][1]);
      ctx.closePath();
    }
    ctx.fill();
  }
  // error bars and markers each in their own element's style, as the SVG writer leaves
  // them (Plotly may style them point by point)
  ticks.forEach(([x, hi, lo], k) => {
    stroke(ctx, bars[k].style);
    ctx.beginPath();
    ctx.moveTo(x - half, hi); ctx.lineTo(x + half, hi);
    ctx.moveTo(x, hi); ctx.lineTo(x, lo);
    ctx.moveTo(x - half, lo); ctx.lineTo(x + half, lo);
    ctx.stroke();
  });
  segs.forEach((run, k) => {
    const style = lines[k].style;
    if (!(px(style.strokeWidth) > 0)) return;
    stroke(ctx, style);
    ctx.beginPath();
    ctx.moveTo(run[0][0], run[0][1]);
    for (let i = 1; i < run.length; i++) ctx.lineTo(run[i][0], run[i][1]);
    ctx.stroke();
  });
  const shapes = new Map();        // a marker's outline by its path (one symbol and size: one)
  marks.forEach((m, k) => {
    const d = m.getAttribute("d") || "", style = m.style, edge = px(style.strokeWidth), [x, y] = drawn[k];
    if (!shapes.has(d)) shapes.set(d, new Path2D(d));
    ctx.fillStyle = style.fill;
    ctx.globalAlpha = alpha(style.fillOpacity, style.opacity);
    ctx.translate(x, y);
    ctx.fill(shapes.get(d));
    if (edge > 0) {
      stroke(ctx, style);
      ctx.setLineDash([]);
      ctx.stroke(shapes.get(d));
    }
    ctx.translate(-x, -y);
  });
}

/** Draws `data` on the canvas over `gd` as svgpaths.js would write it, and hides the SVG
 * traces; false, and nothing drawn, if it cannot. gd.heldCurves: the line runs drawn
 * (pixel points in each trace's layer), for the tests. */
export function drawHeld(gd, data) {
  const svg = gd.querySelector(".svg-container > svg.main-svg");
  const traces = svg && geometry(gd, data);
  if (!traces) return false;
  const placed = traces.map((t) => ({ t, at: offset(t.group), clip: clipOf(t.group) }));
  if (placed.some((p) => !p.at || p.clip === null)) return false;
  const surface = canvasOf(gd, svg), ctx = surface.getContext("2d"), r = surface.width / (px(svg.getAttribute("width")) || 1);
  ctx.setTransform(1, 0, 0, 1, 0, 0);
  ctx.clearRect(0, 0, surface.width, surface.height);
  for (const { t, at, clip } of placed) {
    ctx.save();
    ctx.setTransform(r, 0, 0, r, 0, 0);
    if (clip) ctx.clip(clip);
    ctx.translate(at[0], at[1]);
    drawTrace(ctx, t);
    ctx.restore();
  }
  gd.heldCurves = traces.map((t) => t.segs);
  if (!gd.classList.contains(HELD)) gd.classList.add(HELD);
  return true;
}

/** A plot's canvas made, at its size, and given its (blank) pixels before a drag: the
 * first held frames then only draw (making the canvas, its first pixels and its
 * compositor layer cost the first held frame of each panel up to 6 ms more). */
export function readyHeld(gd) {
  const svg = gd.querySelector(".svg-container > svg.main-svg");
  if (!svg || gd.classList.contains(HELD)) return;      // drawing on it already
  const surface = canvasOf(gd, svg), ready = `${surface.width}x${surface.height}`;
  if (gd.dataset.heldReady === ready) return;
  surface.getContext("2d").clearRect(0, 0, surface.width, surface.height);
  gd.dataset.heldReady = ready;
}

/** The SVG traces shown again (they show the data now: written, or drawn by Plotly)
 * and the canvas cleared. */
export function endHeld(gd) {
  if (!gd.classList.contains(HELD)) return;
  gd.classList.remove(HELD);
  gd.heldCurves = null;
  const surface = gd.querySelector(`canvas.${HELD}-layer`)?.surface;
  surface?.getContext("2d").clearRect(0, 0, surface.width, surface.height);
}
