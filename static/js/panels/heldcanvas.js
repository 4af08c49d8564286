/* While a slider is held, the curves drawn on a canvas laid over the plot.
 *
 * Writing a trace's SVG paths (svgpaths.js) costs the page's main thread the path
 * strings, then Blink's style, layout, paint and layerisation of the changed paths: a
 * frame that redrew four panels took 7-10 ms, one that only moved the slider 3-4 ms
 * (BENCHMARKS.md §5), and the slider's input events waited behind it. On a canvas the
 * same points are a few hundred lineTo calls and the SVG underneath is not touched; the
 * canvas's OffscreenCanvas is handed to a worker (heldworker.js), which draws there, so
 * its frames go to the compositor without the page's paint and commit and the main
 * thread neither issues the 2-D calls nor finalises the frames (7.97 → 6.78 ms of main
 * thread a drag event, BENCHMARKS.md §5). The points are the ones svgpaths.js would
 * write (its geometry()), in the styles read from the elements Plotly drew, clipped as
 * Plotly clips them; on release the SVG is written again and the canvas cleared (endHeld).
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

/** The clip of a trace group in the SVG's pixels (its nearest clip-path: a rect, or a
 * path and its offset), undefined when it has none, null when it cannot be read. */
function clipOf(group) {
  const owner = group.closest("[clip-path]");
  if (!owner || !group.ownerSVGElement?.contains(owner)) return undefined;
  const id = /url\(["']?#([^"')]+)["']?\)/.exec(owner.getAttribute("clip-path"))?.[1];
  const shape = id && document.getElementById(id)?.firstElementChild;
  const at = offset(owner), own = shape && translation(shape);
  if (!shape || !at || !own) return null;
  at[0] += own[0];
  at[1] += own[1];
  if (shape.tagName === "rect") {
    const n = (a) => Number(shape.getAttribute(a) || 0);
    return { rect: [at[0] + n("x"), at[1] + n("y"), n("width"), n("height")] };
  }
  return shape.tagName === "path" ? { d: shape.getAttribute("d") || "", at } : null;
}

const px = (v) => Number.parseFloat(v) || 0;

/** The drawing thread (heldworker.js), null where a canvas cannot be drawn from a
 * worker (then the held plots keep their SVG). Started with the page: its script (4 kB)
 * is loaded long before the first draw, where one started at the first canvas (made at
 * idle after a draw) was still loading when a visitor followed a link, and the browser
 * reported the cut request as failed. */
const worker = typeof Worker === "function" && "transferControlToOffscreen" in HTMLCanvasElement.prototype
  ? new Worker(new URL("./heldworker.js", import.meta.url), { type: "module" }) : null;
let ids = 0;

/** A plot div's overlay canvas (made once, its surface handed to the worker), sized to
 * its SVG: {id, scale} (scale: device pixels per SVG pixel), null without a worker. */
function canvasOf(gd, svg) {
  if (!worker) return null;
  let cv = gd.querySelector(`canvas.${HELD}-layer`);
  if (!cv) {
    cv = document.createElement("canvas");
    cv.className = `${HELD}-layer`;
    cv.heldId = ++ids;
    svg.after(cv);
    const canvas = cv.transferControlToOffscreen();
    worker.postMessage({ id: cv.heldId, canvas }, [canvas]);
  }
  const width = px(svg.getAttribute("width")), height = px(svg.getAttribute("height")), r = window.devicePixelRatio || 1;
  const size = [Math.round(width * r), Math.round(height * r)];
  if (cv.heldSize?.[0] !== size[0] || cv.heldSize?.[1] !== size[1]) {
    cv.heldSize = size;
    worker.postMessage({ id: cv.heldId, size });       // sizing clears it
    cv.style.width = `${width}px`;
    cv.style.height = `${height}px`;
  }
  return { id: cv.heldId, scale: size[0] / (width || 1) };
}

/** An element's style as the worker draws it. */
function styleOf(node) {
  const s = node.style;
  return { stroke: s.stroke, strokeWidth: s.strokeWidth, strokeOpacity: s.strokeOpacity, opacity: s.opacity,
           strokeDasharray: s.strokeDasharray, fill: s.fill, fillOpacity: s.fillOpacity };
}

/** One placed trace as the worker draws it: its runs are views of one array, whose
 * buffer goes in `buffers` (one transfer a trace: a buffer a run made the post ~50 %
 * dearer, BENCHMARKS.md §5). */
function message({ t, at, clip }, buffers) {
  let total = 0;
  for (const run of t.segs) total += 2 * run.length;
  const points = new Float32Array(total);
  buffers.push(points.buffer);
  let o = 0;
  const runs = t.segs.map((run) => {
    const start = o;
    for (const [x, y] of run) {
      points[o++] = x;
      points[o++] = y;
    }
    return points.subarray(start, o);
  });
  return {
    at, clip, runs, half: t.half,
    fill: t.fill && styleOf(t.fill),
    lines: t.lines.map(styleOf),
    bars: t.ticks.map(([x, hi, lo], k) => ({ style: styleOf(t.bars[k]), x, hi, lo })),
    marks: t.marks.map((m, k) => ({ d: m.getAttribute("d") || "", style: styleOf(m), x: t.drawn[k][0], y: t.drawn[k][1] })),
  };
}

/** Draws `data` on the canvas over `gd` as svgpaths.js would write it (posted to the
 * worker, which draws it for the next frame), and hides the SVG traces; false, and
 * nothing drawn, if it cannot. gd.heldCurves: the line runs drawn (pixel points in each
 * trace's layer), for the tests. */
export function drawHeld(gd, data) {
  const svg = gd.querySelector(".svg-container > svg.main-svg");
  const traces = svg && geometry(gd, data);
  if (!traces) return false;
  const placed = traces.map((t) => ({ t, at: offset(t.group), clip: clipOf(t.group) }));
  if (placed.some((p) => !p.at || p.clip === null)) return false;
  const canvas = canvasOf(gd, svg);
  if (!canvas) return false;
  const buffers = [];
  worker.postMessage({ id: canvas.id, scale: canvas.scale, traces: placed.map((p) => message(p, buffers)) }, buffers);
  gd.heldCurves = traces.map((t) => t.segs);
  if (!gd.classList.contains(HELD)) gd.classList.add(HELD);
  return true;
}

/** A plot's canvas made, at its size, before a drag: the first held frames then only
 * draw (making the canvas, its first pixels and its compositor layer cost the first held
 * frame of each panel up to 6 ms more). A new or resized canvas is blank, and endHeld
 * blanks one that was drawn on. */
export function readyHeld(gd) {
  const svg = gd.querySelector(".svg-container > svg.main-svg");
  if (svg && !gd.classList.contains(HELD)) canvasOf(gd, svg);      // else drawing on it already
}

/** The SVG traces shown again (they show the data now: written, or drawn by Plotly)
 * and the canvas cleared. */
export function endHeld(gd) {
  if (!gd.classList.contains(HELD)) return;
  gd.classList.remove(HELD);
  gd.heldCurves = null;
  const id = gd.querySelector(`canvas.${HELD}-layer`)?.heldId;
  if (id) worker.postMessage({ id, clear: true });
}

// A held frame's writes each in a task of their own, after the frame: in the frame they
// ran as one task with its rendering (four panels' points and posts, 2-5 ms, then paint
// and commit), and an input event due meanwhile waited for all of it; between tasks it
// runs in its turn. A MessageChannel's message is a task that no timer clamping delays.
const channel = new MessageChannel();
const resumes = [];
channel.port1.onmessage = () => resumes.shift()?.();

/** A promise resolved in a task of its own, queued behind the tasks already due. */
export function ownTask() {
  return new Promise((resolve) => {
    resumes.push(resolve);
    channel.port2.postMessage(0);
  });
}

let reads = 0;

/** What a plot's canvas shows (an ImageData, once the worker has drawn what was posted
 * before), or null without one: for the tests. */
export function heldPixels(gd) {
  const id = gd.querySelector(`canvas.${HELD}-layer`)?.heldId;
  if (!id) return Promise.resolve(null);
  const read = ++reads;
  return new Promise((resolve) => {
    const answer = ({ data }) => {
      if (data.read !== read) return;
      worker.removeEventListener("message", answer);
      resolve(data.pixels);
    };
    worker.addEventListener("message", answer);
    worker.postMessage({ id, read });
  });
}
